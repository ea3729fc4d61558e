// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <ros/ros.h>

#include "minco_traj_ros/minco_traj_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "minco_traj");
  ros::NodeHandle nh, private_nh("~");
  try {
    const auto config = efs::traj::loadMincoTrajNodeConfig(private_nh);
    efs::traj::MincoTrajNode node(nh, config);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("minco_traj: %s", e.what());
    ros::shutdown();
    return 1;
  }
  return 0;
}
