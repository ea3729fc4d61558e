// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <ros/ros.h>

#include "marsim_worlds_ros/marsim_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "marsim_node");
  ros::NodeHandle nh, private_nh("~");
  try {
    const auto config = efs::sim::loadMarsimNodeConfig(private_nh);
    efs::sim::MarsimNode node(nh, config);
    node.run();
  } catch (const std::exception& e) {
    ROS_FATAL("marsim_node: %s", e.what());
    ros::shutdown();
    return 1;
  }
  return 0;
}
