// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <ros/ros.h>

#include "prior_map_tools_ros/prior_map_server.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "prior_map_server");
  ros::NodeHandle nh, private_nh("~");
  try {
    const auto config = efs::prior_map::loadPriorMapServerConfig(private_nh);
    efs::prior_map::PriorMapServer server(nh, config);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("prior_map_server: %s", e.what());
    ros::shutdown();
    return 1;
  }
  return 0;
}
