// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/local_planner.h"

#include <cmath>
#include <limits>

#include "efs_common/config_check.h"

namespace efs::traj {

void LocalPlannerConfig::validate() const {
  astar.validate();
  corridor.validate();
  optimizer.validate();
  yaw.validate();
  requireInRange("local_planner.emergency_decel_mps2", emergency_decel_mps2, 0.0, 50.0);
}

const char* toString(PlanStatus s) {
  switch (s) {
    case PlanStatus::kOk:
      return "ok";
    case PlanStatus::kBadRequest:
      return "bad_request";
    case PlanStatus::kStartInCollision:
      return "start_in_collision";
    case PlanStatus::kGoalUnreachable:
      return "goal_unreachable";
    case PlanStatus::kCorridorFailed:
      return "corridor_failed";
    case PlanStatus::kOptimizationFailed:
      return "optimization_failed";
  }
  return "?";
}

LocalPlanner::LocalPlanner(const LocalPlannerConfig& cfg)
    : cfg_(cfg),
      astar_(cfg.astar),
      corridor_(cfg.corridor),
      optimizer_(cfg.optimizer),
      yaw_(cfg.yaw) {
  cfg_.validate();
}

PlanResult LocalPlanner::fail(PlanStatus s, const std::string& msg, const PlanRequest& req,
                              PlanResult&& partial) const {
  PlanResult r = std::move(partial);
  r.status = s;
  r.message = msg;
  r.emergency_stop = true;
  const double decel =
      cfg_.emergency_decel_mps2 > 0.0 ? cfg_.emergency_decel_mps2 : cfg_.optimizer.a_max_mps2;
  const bool finite = req.p_world_m.allFinite() && req.v_world_mps.allFinite();
  const double yaw = std::isfinite(req.yaw_rad) ? req.yaw_rad : 0.0;
  r.trajectory = finite ? emergencyStop(req.p_world_m, req.v_world_mps, decel, yaw) : Trajectory();
  return r;
}

PlanResult LocalPlanner::plan(const LocalGrid& grid, const PlanRequest& req) const {
  PlanResult res;
  if (!req.p_world_m.allFinite() || !req.v_world_mps.allFinite() || !req.a_world_mps2.allFinite() ||
      !req.goal_world_m.allFinite() || !std::isfinite(req.yaw_rad) ||
      !std::isfinite(req.yaw_rate_radps) || (req.has_look_at && !req.look_at_world_m.allFinite()))
    return fail(PlanStatus::kBadRequest, "non-finite value in the request", req, std::move(res));

  res.front_end = astar_.plan(grid, req.p_world_m, req.goal_world_m);
  res.goal_adjusted = res.front_end.goal_adjusted;
  res.start_escaped = res.front_end.start_escaped;
  if (!res.front_end.ok()) {
    const bool start_bad = res.front_end.status == AStarStatus::kStartInCollision ||
                           res.front_end.status == AStarStatus::kStartOutside;
    return fail(start_bad ? PlanStatus::kStartInCollision : PlanStatus::kGoalUnreachable,
                std::string("front end: ") + toString(res.front_end.status), req, std::move(res));
  }
  res.corridor = corridor_.build(res.front_end.path_world_m, grid);
  if (!res.corridor.ok())
    return fail(PlanStatus::kCorridorFailed,
                std::string("corridor: ") + toString(res.corridor.status), req, std::move(res));

  Eigen::Matrix3d head, tail = Eigen::Matrix3d::Zero();
  head << req.p_world_m, req.v_world_mps, req.a_world_mps2;
  tail.col(0) = res.front_end.path_world_m.back();
  res.optimization = optimizer_.optimize(head, tail, res.corridor.polytopes);
  if (!res.optimization.ok())
    return fail(PlanStatus::kOptimizationFailed, "optimiser: " + res.optimization.message, req,
                std::move(res));

  res.trajectory = res.optimization.trajectory;
  const Eigen::Vector3d look = req.has_look_at ? req.look_at_world_m : req.goal_world_m;
  res.trajectory.setYaw(yaw_.plan(req.yaw_rad, req.yaw_rate_radps,
                                  YawPlanner::lookAtYaw(req.p_world_m, look, req.yaw_rad)));
  res.status = PlanStatus::kOk;
  return res;
}

double LocalPlanner::firstCollisionTime(const Trajectory& traj, const LocalGrid& grid,
                                        double t_from_s, double horizon_s, double clearance_m,
                                        double dt_s) {
  if (traj.empty() || !(dt_s > 0.0) || !(clearance_m > 0.0)) return -1.0;
  const double t0 = std::max(0.0, t_from_s);
  const double t_end = std::min(traj.duration(), t_from_s + horizon_s);
  const double d_now = grid.nearestOccupiedDistance(traj.position(t0), clearance_m)
                           .value_or(std::numeric_limits<double>::infinity());
  for (double t = t0; t <= t_end + 1e-12; t += dt_s) {
    const std::optional<double> d = grid.nearestOccupiedDistance(traj.position(t), clearance_m);
    if (d && *d < d_now - 1e-6) return t;
  }
  return -1.0;
}

}  // namespace efs::traj
