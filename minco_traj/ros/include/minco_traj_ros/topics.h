// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Topics of minco_traj_node, relative to its namespace; remap them in launch files.
#pragma once

namespace efs::traj::topics {

// Inputs
constexpr const char* kScanWorld = "scan_world";  // sensor_msgs/PointCloud2, world frame
constexpr const char* kOdom = "odom";  // nav_msgs/Odometry, world frame, twist in body frame
constexpr const char* kTarget = "exploration_target";  // geometry_msgs/PoseStamped, world frame
// Outputs
constexpr const char* kTrajectory = "trajectory";         // PolynomialTrajectory
constexpr const char* kPositionCommand = "position_cmd";  // PositionCommand
constexpr const char* kMarkers = "traj_markers";          // visualization_msgs/MarkerArray
// geometry_msgs/PointStamped: a goal given up (give_up_after_failed_plans), once per goal
constexpr const char* kUnreachableGoal = "unreachable_goal";

}  // namespace efs::traj::topics
