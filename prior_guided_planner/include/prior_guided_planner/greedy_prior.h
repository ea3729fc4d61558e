// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The greedy_prior baseline (after Luperto et al.: frontier utility from the information gain
// predicted on the sketch, chosen greedily). Under the most confident usable hypothesis the
// sketch's traversable samples are put into the world; those the map has not observed yet
// (no surface seen within `observed_radius_m` of them, or only poorly observed surface when
// `poorly_observed_is_unknown`) are the predicted unknown free space.
// A viewpoint's gain is the predicted unknown free area within `sensor_range_m` (horizontal) of
// it; its utility is gain / (L(X_r, V) + length_offset_m). The robot goes to the viewpoint of
// highest utility (ties: the nearer one). Walls of the sketch are not ray cast: the gain is an
// area estimate, like the baseline's.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "prior_guided_planner/planner_types.h"

namespace efs::planner {

struct GreedyPriorConfig {
  /// Predicted free space within this horizontal distance of a viewpoint is its gain [m].
  double sensor_range_m = 10.0;
  /// A predicted free sample counts as observed when the map saw surface this close to it [m].
  double observed_radius_m = 1.0;
  /// Count samples whose surroundings are only poorly observed as unknown (the other modes
  /// also revisit poorly observed surface, EPIC's criterion); false: any observation counts.
  bool poorly_observed_is_unknown = true;
  /// utility = gain / (path length + this) [m]; keeps a viewpoint at the robot finite.
  double length_offset_m = 1.0;
  void validate() const;
};

/// The prior's predicted free samples in the world frame (xy) under `hypothesis` that
/// `observation` reports as unseen (all of them when `observation` is empty).
std::vector<Eigen::Vector2d> unobservedPredictedFree(const GuidepointPrior& prior,
                                                     const Hypothesis& hypothesis,
                                                     const ObservationQuery& observation,
                                                     const GreedyPriorConfig& config);

struct GreedyPriorScores {
  std::vector<double> gain_m2;  ///< per viewpoint: predicted unknown free area in range
  std::vector<double> utility;  ///< per viewpoint; 0 when unreachable or without gain
  int best = -1;                ///< highest utility; -1 when no reachable viewpoint gains
};

/// Scores every viewpoint. `robot_to_viewpoint_m[i]` = L(X_r, V_i) (kUnreachable allowed);
/// each sample of `unobserved_world_m` stands for `sample_area_m2`.
GreedyPriorScores scoreGreedyPrior(const std::vector<PlanViewpoint>& viewpoints,
                                   const std::vector<double>& robot_to_viewpoint_m,
                                   const std::vector<Eigen::Vector2d>& unobserved_world_m,
                                   double sample_area_m2, const GreedyPriorConfig& config);

}  // namespace efs::planner
