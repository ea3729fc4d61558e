// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <ros/ros.h>

#include "prior_guided_planner_ros/prior_guided_planner.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "prior_guided_planner");
  ros::NodeHandle nh, private_nh("~");
  try {
    const auto config = efs::planner::loadPriorGuidedPlannerConfig(private_nh);
    efs::planner::PriorGuidedPlannerNode node(nh, config);
    ros::spin();
    // Shut down (Ctrl-C, roslaunch ending, the drone landing): what was explored is kept.
    if (!config.map_output_dir.empty()) node.saveMap("node shutting down");
  } catch (const std::exception& e) {
    ROS_FATAL("prior_guided_planner: %s", e.what());
    ros::shutdown();
    return 1;
  }
  return 0;
}
