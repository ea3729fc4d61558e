// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Topics of marsim_node, relative to its namespace; remap them in launch files. The LIO-shaped
// outputs carry FAST-LIO2's names so the rest of the graph cannot tell simulation from flight.
#pragma once

namespace efs::sim::topics {

// Inputs
constexpr const char* kSo3Command = "so3_cmd";              // SO3Command
constexpr const char* kAttitudeTarget = "attitude_target";  // AttitudeTarget
// Outputs
constexpr const char* kCloudRegistered = "cloud_registered";  // PointCloud2, LIO frame
constexpr const char* kOdometry = "Odometry";                 // nav_msgs/Odometry, LIO frame
constexpr const char* kGroundTruth = "ground_truth/odom";     // nav_msgs/Odometry, true state
constexpr const char* kImu = "imu";                           // sensor_msgs/Imu, body frame
constexpr const char* kStatus = "sim_status";                 // SimulatorStatus

}  // namespace efs::sim::topics
