// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Topics of prior_guided_planner_node, relative to its namespace; remap them in launch files.
#pragma once

namespace efs::planner::topics {

// Inputs
constexpr const char* kScanWorld = "scan_world";   // sensor_msgs/PointCloud2, world frame
constexpr const char* kOdom = "odom";              // nav_msgs/Odometry, world frame
constexpr const char* kHypotheses = "hypotheses";  // RegistrationHypotheses
// geometry_msgs/PointStamped from minco_traj: the local planner gave up on this goal
constexpr const char* kUnreachableGoal = "unreachable_goal";
// Outputs
constexpr const char* kTarget = "exploration_target";   // geometry_msgs/PoseStamped (goal + yaw)
constexpr const char* kLookAt = "exploration_look_at";  // geometry_msgs/PointStamped
constexpr const char* kTour = "exploration_tour";       // nav_msgs/Path: robot + local tour
constexpr const char* kStatus = "exploration_status";   // ExplorationStatus
constexpr const char* kGuidepoints = "guidepoints";     // Guidepoints (states, sketch frame)
constexpr const char* kMarkers = "planner_markers";     // visualization_msgs/MarkerArray
// Services
constexpr const char* kSaveMap = "save_map";  // std_srvs/Trigger: write the mission map now

}  // namespace efs::planner::topics
