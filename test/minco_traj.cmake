efs_rostest_gtest(minco_traj_rostest minco_traj.test
  SOURCES ros/minco_traj_rostest.cpp DEPENDS efs_minco_traj_ros)
