// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <ros/ros.h>

#include "sketch_registration_ros/sketch_registration_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "sketch_registration");
  ros::NodeHandle nh, private_nh("~");
  try {
    const auto config = efs::registration::loadSketchRegistrationNodeConfig(private_nh);
    efs::registration::SketchRegistrationNode node(nh, config);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("sketch_registration: %s", e.what());
    ros::shutdown();
    return 1;
  }
  return 0;
}
