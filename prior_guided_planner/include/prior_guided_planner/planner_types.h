// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The abstract inputs of the hierarchical planner (paper Sec. VI), independent of how the map,
// frontiers and viewpoints are produced:
//  - viewpoints: world-frame poses with ids (PlanViewpoint),
//  - a path-length oracle L(a, b) over the robot and the viewpoints,
//  - registration hypotheses: Sim2 (sketch -> world) + confidence,
//  - the prior's guidepoints in the sketch frame + their PRM distance matrix.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "efs_common/sim2.h"
#include "prior_guided_planner/cost_matrix.h"

namespace efs::planner {

/// A local viewpoint as the hierarchical planner sees it.
struct PlanViewpoint {
  int id = -1;
  Eigen::Vector3d position_world_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
};

/// Node index of the robot for PathLengthFn; viewpoints are 0..N-1 (their index in the input).
inline constexpr int kRobotNode = -1;

/// Searched path length L(from, to) [m] between planner nodes; kUnreachable when there is none.
using PathLengthFn = std::function<double(int from, int to)>;

/// One registration hypothesis: p_world_xy = T_world_sketch * p_sketch.
struct Hypothesis {
  int id = 0;
  Sim2 T_world_sketch;
  double confidence = 1.0;
};

/// Why a hypothesis cannot be used (non-finite transform, non-positive scale, bad confidence);
/// std::nullopt when it is usable.
std::optional<std::string> hypothesisDefect(const Hypothesis& h);

/// The prior's guidepoints (sketch frame) and their PRM shortest-path lengths [sketch m].
/// PRM pairs without a connecting path hold kUnreachable.
struct GuidepointPrior {
  std::vector<uint32_t> ids;
  std::vector<Eigen::Vector2d> positions_sketch_m;
  CostMatrix prm_distance_m;
  /// Samples of the sketch's traversable space (sketch frame), each standing for
  /// `predicted_free_cell_m`^2 of predicted free area; the greedy_prior baseline's information
  /// gain. May be empty (then greedy_prior has nothing to predict and runs prior-free).
  std::vector<Eigen::Vector2d> predicted_free_sketch_m;
  double predicted_free_cell_m = 1.0;

  int size() const { return static_cast<int>(positions_sketch_m.size()); }
  /// Throws std::invalid_argument naming the defect (sizes, NaN, negative distances, free
  /// samples).
  void validate() const;
};

/// Observation state around a point, as classified by the observation map (EPIC criteria).
enum class ObservationLevel { kNone, kPoorlyObserved, kWellObserved };

/// Best observation level of surface points within `radius_m` of a world-frame point.
using ObservationQuery =
    std::function<ObservationLevel(const Eigen::Vector2d& center_world_m, double radius_m)>;

}  // namespace efs::planner
