// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The hierarchical planner's abstract inputs (planner_types.h) built from the map part:
// viewpoints, the observation query for guidepoint states, and the path-length oracle.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "prior_guided_planner/observation_map.h"
#include "prior_guided_planner/path_length.h"
#include "prior_guided_planner/planner_types.h"
#include "prior_guided_planner/viewpoint_sampler.h"

namespace efs::planner {

/// Cache id of the robot node (viewpoint ids are small non-negative integers).
inline constexpr uint64_t kRobotPathNodeId = ~uint64_t(0);

/// Every viewpoint of the manager, ordered by cluster then rank.
std::vector<PlanViewpoint> toPlanViewpoints(const ViewpointManager& viewpoints);

/// ObservationQuery over the map's vertical columns. The map must outlive the query.
ObservationQuery makeObservationQuery(const ObservationMap& map);

/// PathLengthFn over kRobotNode (at `robot_world_m`) and viewpoints 0..N-1 of `viewpoints`,
/// served by `cache` (keys: kRobotPathNodeId and the viewpoint ids); kUnreachable when there
/// is no path. `cache` and `viewpoints` must outlive the function.
PathLengthFn makePathLengthFn(PathLengthCache& cache, const Eigen::Vector3d& robot_world_m,
                              const std::vector<PlanViewpoint>& viewpoints);

/// L(X_r, V_i) = L(V_i, X_r) = `robot_to_viewpoint_m[i]` (kUnreachable allowed; e.g. from one
/// PathSearch::lengthsFrom), viewpoint pairs from `cache`. Both vectors and `cache` must outlive
/// the function.
PathLengthFn makePathLengthFn(PathLengthCache& cache,
                              const std::vector<double>& robot_to_viewpoint_m,
                              const std::vector<PlanViewpoint>& viewpoints);

}  // namespace efs::planner
