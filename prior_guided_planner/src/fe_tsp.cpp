// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/fe_tsp.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "efs_common/angles.h"
#include "efs_common/config_check.h"

namespace efs::planner {

void FeTspConfig::validate() const {
  requirePositive("fe_tsp.v_max_mps", v_max_mps);
  requirePositive("fe_tsp.omega_max_radps", omega_max_radps);
  // |beta_e| <= 1 keeps J(X_r, V) >= 0: max(a, b) + beta_e * b >= (1 + beta_e) * b.
  requireInRange("fe_tsp.beta_e", beta_e, -1.0, 1.0);
  requireInRange("fe_tsp.direction_change_cost_s_per_rad", direction_change_cost_s_per_rad, 0.0,
                 100.0);
  requireInRange("fe_tsp.direction_min_speed_mps", direction_min_speed_mps, 0.0, 100.0);
  requireInRange("fe_tsp.velocity_change_accel_mps2", velocity_change_accel_mps2, 0.0, 100.0);
  atsp.validate();
}

CostMatrix buildFeTspMatrix(const RobotPose& robot, const std::vector<PlanViewpoint>& viewpoints,
                            const std::vector<int>& selected, const std::vector<bool>& isolated,
                            const std::optional<Eigen::Vector2d>& terminal_world_m,
                            const PathLengthFn& path_length_m, const FeTspConfig& config) {
  config.validate();
  if (!path_length_m) throw std::invalid_argument("buildFeTspMatrix: no path length oracle");
  if (isolated.size() != selected.size())
    throw std::invalid_argument("buildFeTspMatrix: isolated flags do not match the selection");
  const int n = static_cast<int>(selected.size());
  const bool term = terminal_world_m.has_value();
  const int size = term ? n + 3 : n + 1;
  const int t = n + 1, dv = n + 2;
  CostMatrix c(size, kUnreachable);
  for (int i = 0; i < size; ++i) c(i, i) = 0.0;
  const Eigen::Vector2d v_xy = robot.velocity_world_mps.head<2>();
  // A terminal gives the tour its direction (the guidance); without one, the robot's motion does.
  const bool moving = !term && config.direction_change_cost_s_per_rad > 0.0 && v_xy.allFinite() &&
                      v_xy.norm() >= std::max(config.direction_min_speed_mps, 1e-6);
  const double heading_rad = moving ? std::atan2(v_xy.y(), v_xy.x()) : 0.0;
  for (int a = 0; a < n; ++a) {
    const PlanViewpoint& va = viewpoints.at(selected[a]);
    const double l = path_length_m(kRobotNode, selected[a]);
    const double dyaw_s = std::abs(angleDiff(va.yaw_rad, robot.yaw_rad)) / config.omega_max_radps;
    const double urg = isolated[a] ? config.beta_e * dyaw_s : 0.0;
    double turn_s = 0.0;
    const Eigen::Vector2d to_v = va.position_world_m.head<2>() - robot.position_world_m.head<2>();
    if (moving && to_v.norm() > 1e-6) {
      turn_s = config.direction_change_cost_s_per_rad *
               std::abs(angleDiff(std::atan2(to_v.y(), to_v.x()), heading_rad));
    }
    // Planar, as the direction term: the vehicle climbs and turns on separate axes.
    if (!term && config.velocity_change_accel_mps2 > 0.0 && v_xy.allFinite() && to_v.norm() > 1e-6)
      turn_s +=
          (config.v_max_mps * to_v.normalized() - v_xy).norm() / config.velocity_change_accel_mps2;
    c(0, a + 1) =
        l < kUnreachable ? std::max(l / config.v_max_mps, dyaw_s) + urg + turn_s : kUnreachable;
    c(a + 1, 0) = 0.0;
    for (int b = 0; b < n; ++b) {
      if (a == b) continue;
      const double lab = path_length_m(selected[a], selected[b]);
      c(a + 1, b + 1) = lab < kUnreachable ? lab / config.v_max_mps : kUnreachable;
    }
    if (term)
      c(a + 1, t) = (va.position_world_m.head<2>() - *terminal_world_m).norm() / config.v_max_mps;
  }
  if (term) {
    c(t, dv) = 0.0;
    c(dv, 0) = 0.0;
    if (n == 0) c(0, t) = 0.0;  // nothing to visit: go straight towards the terminal
    // Every other edge at G_t / G_v stays kUnreachable (the paper's "infinity").
  }
  for (int i = 0; i < size; ++i)
    for (int j = 0; j < size; ++j)
      if (std::isnan(c(i, j)))
        throw std::invalid_argument("buildFeTspMatrix: path length oracle returned NaN");
  return c;
}

namespace {

LocalTour solveOver(const RobotPose& robot, const std::vector<PlanViewpoint>& viewpoints,
                    std::vector<int> wanted, const std::vector<bool>& wanted_iso,
                    const std::optional<Eigen::Vector2d>& terminal, const PathLengthFn& L,
                    const FeTspConfig& config, const std::vector<int>* warm_ids) {
  config.validate();
  if (!L) throw std::invalid_argument("FE-TSP: no path length oracle");
  LocalTour out;
  std::vector<int> sel;
  std::vector<bool> iso;
  for (size_t k = 0; k < wanted.size(); ++k) {
    if (wanted[k] < 0 || wanted[k] >= static_cast<int>(viewpoints.size()))
      throw std::invalid_argument("FE-TSP: viewpoint index " + std::to_string(wanted[k]) +
                                  " out of range");
    if (L(kRobotNode, wanted[k]) < kUnreachable) {
      sel.push_back(wanted[k]);
      iso.push_back(wanted_iso[k]);
    } else {
      out.unreachable_viewpoints.push_back(wanted[k]);
    }
  }
  out.has_terminal = terminal.has_value();
  if (terminal) out.terminal_world_m = *terminal;
  const CostMatrix c = buildFeTspMatrix(robot, viewpoints, sel, iso, terminal, L, config);
  const int n = static_cast<int>(sel.size());
  // The warm start: the robot, the viewpoints of the preferred order that are still selected,
  // in that order, then the rest, then G_t and G_v. J(V, X_r) = 0 makes the closed tour a path
  // with a free end, which is what the solver warm-starts. When none of the preferred order is
  // left the solver starts from the assignment relaxation as without a warm start.
  std::vector<int> warm;
  int kept = 0;
  if (warm_ids && !warm_ids->empty()) {
    std::unordered_map<int, int> node_of_id;
    for (int k = 0; k < n; ++k) node_of_id.emplace(viewpoints[sel[k]].id, k + 1);
    std::vector<bool> placed(n + 1, false);
    warm.push_back(0);
    for (int id : *warm_ids) {
      const auto it = node_of_id.find(id);
      if (it == node_of_id.end() || placed[it->second]) continue;
      placed[it->second] = true;
      warm.push_back(it->second);
      ++kept;
    }
    for (int k = 1; k <= n; ++k)
      if (!placed[k]) warm.push_back(k);
    if (terminal) {
      warm.push_back(n + 1);
      warm.push_back(n + 2);
    }
  }
  const AtspSolver solver(config.atsp);
  const AtspResult r =
      kept > 0 ? solver.solveOpenPath(c, 0, AtspSolver::kFreeEnd, config.atsp.seed, &warm)
               : solver.solveTour(c);
  for (size_t k = 1; k < r.order.size(); ++k)
    if (r.order[k] >= 1 && r.order[k] <= n) out.viewpoints.push_back(sel[r.order[k] - 1]);
  out.feasible = r.feasible;
  if (terminal) {
    // Valid FE-TSP tour: X_r, all viewpoints, G_t, G_v.
    out.feasible = out.feasible && r.order.size() == static_cast<size_t>(n + 3) &&
                   r.order[n + 1] == n + 1 && r.order[n + 2] == n + 2;
  }
  out.cost_s = r.cost;
  return out;
}

}  // namespace

LocalTour solveFeTsp(const RobotPose& robot, const std::vector<PlanViewpoint>& viewpoints,
                     const std::vector<int>& isolated, const std::vector<int>& target,
                     const std::optional<Eigen::Vector2d>& terminal_world_m,
                     const PathLengthFn& path_length_m, const FeTspConfig& config,
                     const std::vector<int>* warm_start_ids) {
  std::vector<int> wanted = isolated;
  std::vector<bool> iso(isolated.size(), true);
  for (int v : target)
    if (std::find(isolated.begin(), isolated.end(), v) == isolated.end())
      wanted.push_back(v), iso.push_back(false);
  return solveOver(robot, viewpoints, wanted, iso, terminal_world_m, path_length_m, config,
                   warm_start_ids);
}

LocalTour solvePriorFreeTour(const RobotPose& robot, const std::vector<PlanViewpoint>& viewpoints,
                             const PathLengthFn& path_length_m, const FeTspConfig& config,
                             const std::vector<int>* warm_start_ids) {
  std::vector<int> all(viewpoints.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  return solveOver(robot, viewpoints, all, std::vector<bool>(all.size(), false), std::nullopt,
                   path_length_m, config, warm_start_ids);
}

}  // namespace efs::planner
