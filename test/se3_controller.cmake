efs_rostest_gtest(se3_controller_rostest se3_controller.test
  SOURCES ros/se3_controller_rostest.cpp DEPENDS efs_common)
