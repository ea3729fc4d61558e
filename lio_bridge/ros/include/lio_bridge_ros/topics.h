// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Topics of lio_bridge_node, relative to its namespace; remap them in launch files. The inputs
// default to FAST-LIO2's names.
#pragma once

namespace efs::lio::topics {

// Inputs
constexpr const char* kLioCloud = "cloud_registered";  // sensor_msgs/PointCloud2, LIO frame
constexpr const char* kLioOdometry = "Odometry";       // nav_msgs/Odometry, LIO frame, no twist
constexpr const char* kImu = "imu";                    // sensor_msgs/Imu (gravity alignment only)
// Outputs
constexpr const char* kOdom = "odom";                             // nav_msgs/Odometry with twist
constexpr const char* kScanWorld = "scan_world";                  // sensor_msgs/PointCloud2
constexpr const char* kLocalMap = "local_map";                    // sensor_msgs/PointCloud2
constexpr const char* kRegistrationFrame = "registration_frame";  // RegistrationFrame
constexpr const char* kStatus = "lio_status";                     // LioStatus

}  // namespace efs::lio::topics
