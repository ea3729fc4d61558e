// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// rviz markers of the exploration manager's state (all in the world frame): viewpoints coloured
// by group, guidepoints under the active hypothesis coloured by state, the selected global
// guidepoint sequence, the local tour, the goal, and the frontier cells coloured by cluster.
#pragma once

#include <geometry_msgs/Point.h>
#include <visualization_msgs/MarkerArray.h>

#include <cstddef>

#include "prior_guided_planner/exploration_manager.h"

namespace efs::planner {

struct PlannerMarkerOptions {
  /// At most this many frontier cells are drawn (evenly strided beyond).
  size_t max_frontier_cells = 20000;
  /// Height [m] at which the 2D guidepoints and the sequence are drawn.
  double guidepoint_z_m = 1.0;
};

geometry_msgs::Point toPointMsg(const Eigen::Vector3d& p);

/// Starts with a DELETEALL so that stale markers disappear.
visualization_msgs::MarkerArray plannerMarkers(const ExplorationManager& manager,
                                               const RobotPose& robot,
                                               const std_msgs::Header& header,
                                               const PlannerMarkerOptions& options);

}  // namespace efs::planner
