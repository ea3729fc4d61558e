// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Topics of se3_controller_node, relative to its namespace; remap them in launch files
// (attitude_target to /mavros/setpoint_raw/attitude on PX4).
#pragma once

namespace efs::control::topics {

// Inputs
constexpr const char* kPositionCommand = "position_cmd";  // PositionCommand
constexpr const char* kOdom = "odom";  // nav_msgs/Odometry, world frame, twist in body frame
constexpr const char* kImu = "imu";    // sensor_msgs/Imu (hover-thrust estimate, optional)
// Outputs
constexpr const char* kSo3Command = "so3_cmd";              // SO3Command
constexpr const char* kAttitudeTarget = "attitude_target";  // AttitudeTarget

}  // namespace efs::control::topics
