efs_rostest_gtest(marsim_node_rostest marsim_node.test
  SOURCES ros/marsim_node_rostest.cpp DEPENDS efs_common)
