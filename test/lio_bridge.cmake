efs_rostest_gtest(lio_bridge_rostest lio_bridge.test
  SOURCES ros/lio_bridge_rostest.cpp DEPENDS efs_common_ros)
