# prior_guided_planner_node: target, tour and status from synthetic scans; bad input; a second
# node with a drawn prior bundle (guided status, guidepoint states); bad configuration.
efs_rostest_gtest(prior_guided_planner_rostest prior_guided_planner.test
  SOURCES ros/prior_guided_planner_rostest.cpp DEPENDS efs_prior_guided_planner_ros efs_prior_map_tools efs_common_ros)
