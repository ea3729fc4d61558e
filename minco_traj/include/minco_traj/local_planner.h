// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The local trajectory pipeline of paper Sec. VI-E in one call: A* front end on the local grid ->
// safe flight corridor -> MINCO spatio-temporal optimisation -> yaw toward the look-at point ->
// final feasibility check. Whatever fails, the result carries a trajectory that is safe to fly
// from the current state: the optimised one, or an emergency stop (brake at the acceleration
// limit) with the reason. Also the collision prediction used to trigger replanning when new
// scans reveal obstacles on the current trajectory.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "minco_traj/astar.h"
#include "minco_traj/corridor.h"
#include "minco_traj/local_grid.h"
#include "minco_traj/traj_optimizer.h"
#include "minco_traj/trajectory.h"
#include "minco_traj/yaw_planner.h"

namespace efs::traj {

struct LocalPlannerConfig {
  /// Weighted A* (1.5) by default: in cluttered 3D space it expands ~100x fewer cells for paths a
  /// few percent longer, and the corridor + optimiser smooth the result anyway.
  AStarConfig astar = [] {
    AStarConfig c;
    c.heuristic_weight = 1.5;
    c.unknown_cost_factor = 2.0;
    return c;
  }();
  CorridorConfig corridor;
  TrajOptConfig optimizer;
  YawPlannerConfig yaw;
  /// Braking deceleration of the emergency stop; 0 uses optimizer.a_max_mps2.
  double emergency_decel_mps2 = 0.0;
  /// When the plan along the shortest path fails and the vehicle moves at least this fast, the
  /// corridor is seeded through the point where it would stop (braking at this fraction of
  /// optimizer.a_max_mps2) and the optimisation is tried once more.
  double braking_first_min_speed_mps = 0.5;
  double braking_first_decel_fraction = 0.7;
  /// Narrow passages (a 1 m door: the inflation leaves no free cell in it). When no plan is found
  /// with the full clearance, A* and the corridor keep only this much from occupied cell centres
  /// (collision radius 0.25 m + half a cell diagonal 0.087 m + margin), and the trajectory is
  /// flown at narrow_v_max_mps at most, where tracking is tight. 0 turns it off.
  double narrow_clearance_m = 0.36;
  double narrow_v_max_mps = 1.0;
  /// A narrow trajectory may leave its corridor by this much in the final check: the part of
  /// narrow_clearance_m's margin it may use. The penalties keep samples corridor_margin_m
  /// inside, more than half of a door's narrow corridor (0.9 m: 0.18 m wide), and the result
  /// strayed 5-12 mm out of it (seen in ed21 at 0.15 m: the vehicle hovered in a door for 30 s
  /// while every goal beyond it was refused).
  double narrow_corridor_tolerance_m = 0.02;
  void validate() const;
};

struct PlanRequest {
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_world_mps2 = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
  double yaw_rate_radps = 0.0;
  Eigen::Vector3d goal_world_m = Eigen::Vector3d::Zero();
  /// Where the sensor should look (the unexplored region); the goal when unset.
  bool has_look_at = false;
  Eigen::Vector3d look_at_world_m = Eigen::Vector3d::Zero();
};

enum class PlanStatus {
  kOk,
  kBadRequest,         ///< non-finite state or goal
  kStartInCollision,   ///< no escape from the start within the escape radius
  kGoalUnreachable,    ///< goal refused or no path (front_end.status says which)
  kCorridorFailed,     ///< the seed path could not be enclosed
  kOptimizationFailed  ///< no trajectory passed the final check
};
const char* toString(PlanStatus s);

struct PlanResult {
  PlanStatus status = PlanStatus::kBadRequest;
  std::string message;
  /// Always flyable: the plan, or an emergency stop if status != kOk.
  Trajectory trajectory;
  bool emergency_stop = false;
  /// The corridor was seeded through the braking point (the shortest path's failed).
  bool braked_first = false;
  /// Planned with the narrow-passage clearance and speed (the full clearance found no way).
  bool narrow = false;
  bool goal_adjusted = false;
  bool start_escaped = false;
  AStarResult front_end;
  CorridorResult corridor;
  TrajOptResult optimization;
  bool ok() const { return status == PlanStatus::kOk; }
};

class LocalPlanner {
 public:
  explicit LocalPlanner(const LocalPlannerConfig& cfg = {});
  const LocalPlannerConfig& config() const { return cfg_; }
  PlanResult plan(const LocalGrid& grid, const PlanRequest& req) const;

  /// First time in [t_from_s, t_from_s + horizon_s] at which the trajectory passes within
  /// clearance_m of an occupied cell centre, closer than it is at t_from_s (a trajectory that
  /// escapes from a wall it is already near is not a threat), sampled every dt_s; negative if
  /// none. The replanning trigger on new scans: an obstacle seen beside the path, not only on
  /// it, counts (the vehicle has a radius).
  static double firstCollisionTime(const Trajectory& traj, const LocalGrid& grid, double t_from_s,
                                   double horizon_s, double clearance_m = 0.35, double dt_s = 0.02);

 private:
  PlanResult fail(PlanStatus s, const std::string& msg, const PlanRequest& req,
                  PlanResult&& partial) const;
  /// Corridor along `path`, optimisation and yaw into `res`; false with the reason in `why`.
  bool optimizeAlong(const LocalGrid& grid, const PlanRequest& req,
                     const std::vector<Eigen::Vector3d>& path, PlanResult* res, std::string* why,
                     bool narrow = false) const;
  /// Along res->front_end's path, else through the braking point (brakingFirstPath): the
  /// corridor, optimisation and yaw into `res` (the first attempt's, when both fail).
  bool optimizeFrontEndPath(const LocalGrid& grid, const PlanRequest& req, PlanResult* res,
                            std::string* why, bool narrow = false) const;
  /// The whole pipeline with the narrow-passage clearance and speed.
  bool planNarrow(const LocalGrid& grid, const PlanRequest& req, PlanResult* res,
                  std::string* why) const;
  /// The start, the point just past where braking stops, then A* on to the goal (with the
  /// narrow-passage clearance when `narrow`); false when the vehicle is slow, the braking
  /// segment is blocked or no path goes on from there.
  bool brakingFirstPath(const LocalGrid& grid, const PlanRequest& req,
                        std::vector<Eigen::Vector3d>* path, bool narrow = false) const;
  LocalPlannerConfig cfg_;
  AStarPlanner astar_, astar_narrow_;
  CorridorBuilder corridor_, corridor_narrow_;
  TrajOptimizer optimizer_, optimizer_narrow_;
  YawPlanner yaw_;
};

}  // namespace efs::traj
