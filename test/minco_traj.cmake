efs_rostest_gtest(minco_traj_rostest minco_traj.test
  SOURCES ros/minco_traj_rostest.cpp DEPENDS efs_minco_traj_ros)
# The flight stack with the simulator, when marsim_worlds and se3_controller are built too.
if(TARGET marsim_node AND TARGET se3_controller_node)
  efs_rostest_gtest(minco_traj_closed_loop_rostest minco_traj_closed_loop.test
    SOURCES ros/minco_traj_closed_loop_rostest.cpp DEPENDS efs_common_ros)
endif()
