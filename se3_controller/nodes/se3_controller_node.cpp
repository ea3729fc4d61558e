// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <ros/ros.h>

#include "se3_controller_ros/se3_controller_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "se3_controller");
  ros::NodeHandle nh, private_nh("~");
  try {
    const auto config = efs::control::loadSe3ControllerNodeConfig(private_nh);
    efs::control::Se3ControllerNode node(nh, config);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("se3_controller: %s", e.what());
    ros::shutdown();
    return 1;
  }
  return 0;
}
