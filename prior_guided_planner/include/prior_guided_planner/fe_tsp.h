// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Local coverage path planning (paper Sec. VI-D): the FE-TSP ("fixed-end" TSP) from the robot
// X_r through the isolated and target viewpoints to the terminal node G_t (the second next
// guidepoint of the selected prior sequence), turned into an ATSP with the dummy node G_v.
// Matrix layout: 0 = X_r, 1..N = viewpoints, N+1 = G_t, N+2 = G_v. Costs are times [s]:
//   J(X_r, V_i) = max(L / v_max, dyaw / omega_max) + U(V_i) + w_c * dir(V_i) + T_v(V_i),
//                 U = beta_e * dyaw / omega_max for isolated viewpoints (beta_e < 0 makes them
//                 urgent), 0 otherwise; dir = the angle between the robot's horizontal velocity
//                 and the direction to V_i, in tours without a terminal only (our addition,
//                 after FUEL; w_c = 0 is the paper); T_v = the time to turn the horizontal
//                 velocity towards V_i at velocity_change_accel_mps2, likewise (0 in the paper);
//   J(V_i, V_j) = L(V_i, V_j) / v_max;   J(V_j, G_t) = |p_j - p_t|_xy / v_max;
//   J(V_i, X_r) = 0;  J(G_t, G_v) = J(G_v, X_r) = 0;  J(G_t, V_j) = J(X_r, G_v) = J(G_v, G_t)
//   = J(G_v, V) = J(V, G_v) = J(X_r, G_t) = J(G_t, X_r) = kUnreachable.
// Without a terminal (sequence too short) the tour is open-ended: the rows end at X_r for free.
// The prior-free fallback (EPIC-like) is the same cost model over all viewpoints, no urgency,
// no terminal. Viewpoints the robot cannot reach (L(X_r, V) = kUnreachable) are left out and
// reported.
#pragma once

#include <optional>
#include <vector>

#include "prior_guided_planner/atsp_solver.h"
#include "prior_guided_planner/planner_types.h"

namespace efs::planner {

struct FeTspConfig {
  double v_max_mps = 4.0;        ///< paper Table: 4 m/s
  double omega_max_radps = 4.0;  ///< paper Table: 4 rad/s
  double beta_e = -0.2;          ///< urgency weight (paper Table: -0.2)
  /// Motion consistency (after FUEL's c_c; not in the paper): in a tour without a terminal
  /// (prior-free, or a guided one whose sequence is too short), J(X_r, V_i) grows by this much
  /// per radian between the robot's horizontal velocity and the direction to V_i, so that the
  /// next viewpoint lies ahead rather than behind when both cost about the same. A tour with a
  /// terminal keeps the paper's costs: the guidance sets its direction, and turning back for
  /// the guided region is what it asks for. Off by default: at 1.0 s/rad the quick tier's
  /// prior-free flights got 25 % (garage) and 23 % (indoor) shorter, the guided ones 19 % and 17 %
  /// shorter there but 38 % (small cave) and 24 % (SubT) longer (README, "Turning back").
  /// 0: off [s/rad].
  double direction_change_cost_s_per_rad = 0.0;
  /// ... only while the robot moves at least this fast; the direction of a hovering robot means
  /// nothing [m/s].
  double direction_min_speed_mps = 0.5;
  /// The time the vehicle needs to turn its velocity towards V_i at this acceleration,
  /// |v_max u_i - v| / a, added to J(X_r, V_i) in tours without a terminal (like the direction
  /// term): 0 ahead at full speed, 0.94 s at a right angle and 1.33 s to turn back from 4 m/s at
  /// 6 m/s^2. A time rather than a weight; not in the paper, whose costs ignore the robot's
  /// motion. Off by default: on the quick tier it made every method faster (the 16 means -5 %),
  /// prior_free as much as the guided flights, so the sketch's gain did not grow (README,
  /// "Turning back"). 0: off [m/s^2].
  double velocity_change_accel_mps2 = 0.0;
  AtspConfig atsp;
  void validate() const;
};

struct RobotPose {
  Eigen::Vector3d position_world_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
  /// For the motion-consistency cost only; zero when unknown.
  Eigen::Vector3d velocity_world_mps = Eigen::Vector3d::Zero();
};

struct LocalTour {
  /// Viewpoint indices (into the input vector) in visiting order.
  std::vector<int> viewpoints;
  /// Total time cost [s] of the tour on the FE-TSP matrix (ends at G_t when there is one).
  double cost_s = 0.0;
  bool has_terminal = false;
  Eigen::Vector2d terminal_world_m = Eigen::Vector2d::Zero();
  bool feasible = true;
  /// Requested viewpoints left out because L(X_r, V) is unreachable.
  std::vector<int> unreachable_viewpoints;
};

/// The FE-TSP matrix over `robot`, `viewpoints[selected[k]]` (node k+1) and the terminal; node
/// k+1 is isolated iff `isolated[k]`. Exposed for tests.
CostMatrix buildFeTspMatrix(const RobotPose& robot, const std::vector<PlanViewpoint>& viewpoints,
                            const std::vector<int>& selected, const std::vector<bool>& isolated,
                            const std::optional<Eigen::Vector2d>& terminal_world_m,
                            const PathLengthFn& path_length_m, const FeTspConfig& config);

/// FE-TSP over the isolated and target viewpoints to the terminal (std::nullopt: free end).
/// `warm_start_ids`, if given and not empty, are viewpoint ids in a preferred order (the last
/// tour): the solver starts from them, the others after them, and only a tour at most as
/// costly replaces that order.
LocalTour solveFeTsp(const RobotPose& robot, const std::vector<PlanViewpoint>& viewpoints,
                     const std::vector<int>& isolated, const std::vector<int>& target,
                     const std::optional<Eigen::Vector2d>& terminal_world_m,
                     const PathLengthFn& path_length_m, const FeTspConfig& config,
                     const std::vector<int>* warm_start_ids = nullptr);

/// Prior-free fallback: ATSP over all viewpoints from the robot, same cost model, free end.
LocalTour solvePriorFreeTour(const RobotPose& robot, const std::vector<PlanViewpoint>& viewpoints,
                             const PathLengthFn& path_length_m, const FeTspConfig& config,
                             const std::vector<int>* warm_start_ids = nullptr);

}  // namespace efs::planner
