// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Where on a searched path the local planner's goal goes: the exploration manager walks the
// path from the robot (to the next viewpoint, or on along the tour) and stops where the goal
// would leave the local planner's reach, pass the look-ahead length, or, past the first
// viewpoint, turn back toward the robot.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

namespace efs::planner {

/// The last point of `path` (path.front() is the robot; walked in 0.1 m steps) that is within
/// reach (`within_reach(p)`), at most `max_length_m` along the path, and, beyond
/// `outward_after_m` along it, not nearer to path.front() than the farthest point so far (less
/// one step): a goal that came back toward the robot left the vehicle hovering beside it.
/// path.front() when the first step is out of bounds; `path` must not be empty.
Eigen::Vector3d goalAlongPath(const std::vector<Eigen::Vector3d>& path, double max_length_m,
                              double outward_after_m,
                              const std::function<bool(const Eigen::Vector3d&)>& within_reach);

}  // namespace efs::planner
