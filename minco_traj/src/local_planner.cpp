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
  requireInRange("local_planner.braking_first_min_speed_mps", braking_first_min_speed_mps, 0.0,
                 50.0);
  requireInRange("local_planner.braking_first_decel_fraction", braking_first_decel_fraction, 0.1,
                 1.0);
  requireInRange("local_planner.narrow_clearance_m", narrow_clearance_m, 0.0, corridor.clearance_m);
  requireInRange("local_planner.narrow_v_max_mps", narrow_v_max_mps, 0.1, optimizer.v_max_mps);
  requireInRange("local_planner.narrow_corridor_tolerance_m", narrow_corridor_tolerance_m, 0.0,
                 0.05);
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

namespace {

AStarConfig narrowAStar(const LocalPlannerConfig& c) {
  AStarConfig a = c.astar;
  a.narrow_clearance_m = c.narrow_clearance_m;
  return a;
}
CorridorConfig narrowCorridor(const LocalPlannerConfig& c) {
  CorridorConfig k = c.corridor;
  if (c.narrow_clearance_m > 0.0) k.clearance_m = c.narrow_clearance_m;
  return k;
}
TrajOptConfig narrowOptimizer(const LocalPlannerConfig& c) {
  TrajOptConfig o = c.optimizer;
  o.v_max_mps = c.narrow_v_max_mps;
  o.corridor_tolerance_m = std::max(o.corridor_tolerance_m, c.narrow_corridor_tolerance_m);
  return o;
}

}  // namespace

LocalPlanner::LocalPlanner(const LocalPlannerConfig& cfg)
    : cfg_((cfg.validate(), cfg)),
      astar_(cfg.astar),
      astar_narrow_(narrowAStar(cfg)),
      corridor_(cfg.corridor),
      corridor_narrow_(narrowCorridor(cfg)),
      optimizer_(cfg.optimizer),
      optimizer_narrow_(narrowOptimizer(cfg)),
      yaw_(cfg.yaw) {}

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
  std::string why;
  if (res.front_end.ok()) {
    if (optimizeFrontEndPath(grid, req, &res, &why)) return res;
  } else {
    why = std::string("front end: ") + toString(res.front_end.status);
  }
  // No way with the full clearance: a narrow passage, slowly, if there is one.
  if (cfg_.narrow_clearance_m > 0.0) {
    PlanResult narrow = res;
    std::string why_narrow;
    if (planNarrow(grid, req, &narrow, &why_narrow)) return narrow;
    why += "; narrow: " + why_narrow;
  }
  PlanStatus status = PlanStatus::kOptimizationFailed;
  if (!res.front_end.ok()) {
    const bool start_bad = res.front_end.status == AStarStatus::kStartInCollision ||
                           res.front_end.status == AStarStatus::kStartOutside;
    status = start_bad ? PlanStatus::kStartInCollision : PlanStatus::kGoalUnreachable;
  } else if (!res.corridor.ok()) {
    status = PlanStatus::kCorridorFailed;
  }
  return fail(status, why, req, std::move(res));
}

bool LocalPlanner::planNarrow(const LocalGrid& grid, const PlanRequest& req, PlanResult* res,
                              std::string* why) const {
  res->front_end = astar_narrow_.plan(grid, req.p_world_m, req.goal_world_m);
  if (!res->front_end.ok()) {
    *why = std::string("front end: ") + toString(res->front_end.status);
    return false;
  }
  res->goal_adjusted = res->front_end.goal_adjusted;
  res->start_escaped = res->front_end.start_escaped;
  res->narrow = true;
  return optimizeFrontEndPath(grid, req, res, why, true);
}

bool LocalPlanner::optimizeFrontEndPath(const LocalGrid& grid, const PlanRequest& req,
                                        PlanResult* res, std::string* why, bool narrow) const {
  if (optimizeAlong(grid, req, res->front_end.path_world_m, res, why, narrow)) return true;
  // The shortest path may leave in another direction than the vehicle is moving, and a
  // corridor around it then has no room to brake in (each polytope spans its seed's box plus
  // a margin; a narrow one, as through a door, barely more than the door): seed the corridor
  // through the braking point first.
  std::vector<Eigen::Vector3d> braking_path;
  if (!brakingFirstPath(grid, req, &braking_path, narrow)) return false;
  PlanResult second = *res;
  std::string why_second;
  if (!optimizeAlong(grid, req, braking_path, &second, &why_second, narrow)) {
    *why += "; braking first: " + why_second;
    return false;
  }
  second.braked_first = true;
  *res = std::move(second);
  return true;
}

bool LocalPlanner::optimizeAlong(const LocalGrid& grid, const PlanRequest& req,
                                 const std::vector<Eigen::Vector3d>& path, PlanResult* res,
                                 std::string* why, bool narrow) const {
  res->corridor = (narrow ? corridor_narrow_ : corridor_).build(path, grid);
  if (!res->corridor.ok()) {
    *why = std::string("corridor: ") + toString(res->corridor.status);
    return false;
  }
  Eigen::Matrix3d head, tail = Eigen::Matrix3d::Zero();
  head << req.p_world_m, req.v_world_mps, req.a_world_mps2;
  tail.col(0) = path.back();
  res->optimization =
      (narrow ? optimizer_narrow_ : optimizer_).optimize(head, tail, res->corridor.polytopes);
  if (!res->optimization.ok()) {
    *why = "optimiser: " + res->optimization.message;
    return false;
  }
  res->trajectory = res->optimization.trajectory;
  const Eigen::Vector3d look = req.has_look_at ? req.look_at_world_m : req.goal_world_m;
  res->trajectory.setYaw(yaw_.plan(req.yaw_rad, req.yaw_rate_radps,
                                   YawPlanner::lookAtYaw(req.p_world_m, look, req.yaw_rad)));
  res->status = PlanStatus::kOk;
  return true;
}

bool LocalPlanner::brakingFirstPath(const LocalGrid& grid, const PlanRequest& req,
                                    std::vector<Eigen::Vector3d>* path, bool narrow) const {
  const AStarPlanner& astar = narrow ? astar_narrow_ : astar_;
  const double speed = req.v_world_mps.norm();
  // Slow enough to turn within a cell or two: the corridor's margin already holds the stop.
  if (speed < cfg_.braking_first_min_speed_mps) return false;
  const double decel = cfg_.braking_first_decel_fraction * cfg_.optimizer.a_max_mps2;
  // Overshoot the stopping point a little so that the polytope around the braking seed holds the
  // whole stop, whatever the optimiser makes of the time allocation.
  const Eigen::Vector3d stop = req.p_world_m + req.v_world_mps * (speed / (2.0 * decel)) +
                               req.v_world_mps.normalized() * grid.resolution();
  if (!grid.inWindow(stop) || !astar.lineOfSight(grid, req.p_world_m, stop)) return false;
  const AStarResult onward = astar.plan(grid, stop, req.goal_world_m);
  if (!onward.ok() || onward.path_world_m.empty()) return false;
  path->assign({req.p_world_m});
  path->insert(path->end(), onward.path_world_m.begin(), onward.path_world_m.end());
  return true;
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
