efs_rostest_gtest(se3_controller_rostest se3_controller.test
  SOURCES ros/se3_controller_rostest.cpp DEPENDS efs_common)
# The flight stack with the simulator through AttitudeTarget (gtest built by test/minco_traj.cmake).
if(TARGET minco_traj_closed_loop_rostest)
  efs_rostest(se3_controller_attitude_loop.test)
endif()
