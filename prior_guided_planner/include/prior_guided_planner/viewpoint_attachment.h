// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Viewpoint attachment and guidepoint states (paper Sec. VI-A), for one hypothesis:
//  - TransformVps: guidepoints sketch -> world with the hypothesis' Sim2.
//  - AttachVps: viewpoint V_i attaches to guidepoint G_j iff the horizontal distance
//    d(V_i, G_j) < min(rho, min_{m != j} d(V_i, G_m)) (strict: a tie attaches to none).
//  - States: exploring = has attached viewpoints; explored = none attached and well-observed
//    points within the influence radius; unexplored = otherwise (nothing, or only poorly
//    observed points, seen there: the place still needs a visit).
//  - Beyond the paper (seen_fraction > 0): a guidepoint also counts as explored, viewpoints or
//    not, once that share of the sketch's free space around it (the predicted free samples
//    nearer to it than to any other guidepoint, within rho) lies under well observed surface.
//    The viewpoints left there wait outside the guided tour until the guidance runs out (then
//    the prior-free tour takes them). Attached viewpoints alone never let a guidepoint go in a
//    place whose every pass leaves new fragments of poorly observed surface at the edge of the
//    well observed band (the paper garage: 442 frontier clusters at 300 s, all within 15 m of
//    the flown path, 388 of them seen from no closer than 12 m): there, 84 of 88 guidepoints
//    stayed exploring, and the guided tour went back and forth between their leftovers.
//  - Guidepoints that land outside the exploration bounds (plus a margin) are `kOutside`: a
//    wrong hypothesis can throw them far away; they take no part in attachment or sequencing.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "prior_guided_planner/planner_types.h"

namespace efs::planner {

struct AttachmentConfig {
  /// Maximum attachment radius rho (paper Table: 20 m).
  double rho_m = 20.0;
  /// Radius around a guidepoint searched for observed points when it has no viewpoint.
  double influence_radius_m = 5.0;
  /// Guidepoints farther than this outside the exploration bounds are kOutside.
  double outside_margin_m = 20.0;
  /// A guidepoint is explored once this share of its predicted free samples lies under well
  /// observed surface (see above); 0: the paper's states only.
  double seen_fraction = 0.0;
  /// ... unless one of its viewpoints lies within this horizontal distance of the robot: what
  /// is left beside the vehicle is taken now, not on a trip back at the end (seen: the small
  /// SubT cave's guided flight left three viewpoints 20 m west as it turned east, and came
  /// back for them after its last guidepoint, 54.3 -> 73.5 s) [m].
  double seen_keep_radius_m = 0.0;
  void validate() const;
};

enum class GuidepointState { kUnexplored, kExploring, kExplored, kOutside };
const char* toString(GuidepointState s);

struct HypothesisAttachment {
  std::vector<Eigen::Vector2d> guidepoints_world_m;
  std::vector<GuidepointState> states;
  /// Per viewpoint: index of the guidepoint it is attached to, or -1.
  std::vector<int> attached_to;
  /// Per guidepoint: indices of its attached viewpoints.
  std::vector<std::vector<int>> attached;
};

/// `robot_xy_world_m`: where the robot is, for seen_keep_radius_m (none: no viewpoint is near).
/// `observation` may be empty (then every guidepoint without viewpoints is unexplored);
/// `bounds_world_m` may be empty (no guidepoint is outside). The hypothesis must be usable
/// (hypothesisDefect() empty), else std::invalid_argument.
HypothesisAttachment attachViewpoints(const Hypothesis& hypothesis, const GuidepointPrior& prior,
                                      const std::vector<PlanViewpoint>& viewpoints,
                                      const ObservationQuery& observation,
                                      const std::optional<Eigen::AlignedBox2d>& bounds_world_m,
                                      const AttachmentConfig& config,
                                      const std::optional<Eigen::Vector2d>& robot_xy_world_m = {});

}  // namespace efs::planner
