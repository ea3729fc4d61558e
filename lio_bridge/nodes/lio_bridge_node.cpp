// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <ros/ros.h>

#include "lio_bridge_ros/lio_bridge.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "lio_bridge");
  ros::NodeHandle nh, private_nh("~");
  try {
    const auto config = efs::lio::loadLioBridgeConfig(private_nh);
    efs::lio::LioBridge bridge(nh, config);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("lio_bridge: %s", e.what());
    ros::shutdown();
    return 1;
  }
  return 0;
}
