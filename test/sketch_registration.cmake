# sketch_registration_node: hypotheses and markers from registration frames; bad input and bad
# bundles.
efs_rostest_gtest(sketch_registration_rostest sketch_registration.test
  SOURCES ros/sketch_registration_rostest.cpp
  DEPENDS efs_sketch_registration efs_prior_map_tools efs_common_ros efs_common)
