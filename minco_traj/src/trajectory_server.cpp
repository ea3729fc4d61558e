// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/trajectory_server.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "efs_common/config_check.h"

namespace efs::traj {

void TrajectoryServerConfig::validate() const {
  planner.validate();
  grid.validate();
  requireInRange("trajectory_server.replan_period_s", replan_period_s, 0.01, 100.0);
  requireInRange("trajectory_server.replan_horizon_remaining_s", replan_horizon_remaining_s, 0.0,
                 100.0);
  requireInRange("trajectory_server.collision_check_horizon_s", collision_check_horizon_s, 0.0,
                 100.0);
  requireInRange("trajectory_server.collision_check_clearance_m", collision_check_clearance_m,
                 grid.resolution_m,
                 std::min(planner.corridor.clearance_m, grid.inflation_radius_m));
  requireInRange("trajectory_server.goal_reached_m", goal_reached_m, 0.01, 100.0);
  requireInRange("trajectory_server.plan_from_future_s", plan_from_future_s, 0.0, 1.0);
  requireInRange("trajectory_server.retry_after_failed_plan_s", retry_after_failed_plan_s, 0.0,
                 replan_period_s);
  requireInRange("trajectory_server.max_retry_backoff_s", max_retry_backoff_s, 0.0, 60.0);
  requireInRange("trajectory_server.new_question_distance_m", new_question_distance_m, 0.0, 1e4);
  requireInRange("trajectory_server.give_up_after_failed_plans", give_up_after_failed_plans, 1,
                 1000);
  requireInRange("trajectory_server.max_tracking_error_m", max_tracking_error_m, 0.01, 100.0);
  requireInRange("trajectory_server.recenter_distance_m", recenter_distance_m, 0.0,
                 0.5 * std::min(grid.size_x_m, grid.size_y_m));
}

const char* toString(ServerEvent e) {
  switch (e) {
    case ServerEvent::kNone:
      return "none";
    case ServerEvent::kReplanned:
      return "replanned";
    case ServerEvent::kPlanFailedKeptCourse:
      return "plan_failed_kept_course";
    case ServerEvent::kEmergencyStop:
      return "emergency_stop";
    case ServerEvent::kGoalReached:
      return "goal_reached";
    case ServerEvent::kRejectedInput:
      return "rejected_input";
    case ServerEvent::kSameGoal:
      return "same_goal";
  }
  return "?";
}

namespace {

const TrajectoryServerConfig& validated(const TrajectoryServerConfig& c) {
  c.validate();
  return c;
}

std::string vecString(const Eigen::Vector3d& v) {
  std::ostringstream os;
  os << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return os.str();
}

}  // namespace

namespace {
/// The grid keeps its narrow inflation at the planner's narrow clearance, so a narrow-passage
/// search asks one cell per step.
LocalGridConfig withNarrowLayer(LocalGridConfig grid, double narrow_clearance_m) {
  grid.narrow_radius_m = narrow_clearance_m;
  return grid;
}
}  // namespace

TrajectoryServer::TrajectoryServer(const TrajectoryServerConfig& config)
    : cfg_(validated(config)),
      grid_(withNarrowLayer(cfg_.grid, cfg_.planner.narrow_clearance_m), Eigen::Vector3d::Zero()),
      planner_(cfg_.planner) {}

void TrajectoryServer::followWith(const Eigen::Vector3d& p_world_m, bool may_move) {
  const Eigen::Vector3d offset = p_world_m - 0.5 * (grid_.windowMin() + grid_.windowMax());
  const bool far = offset.head<2>().norm() > cfg_.recenter_distance_m ||
                   std::abs(offset.z()) > 0.25 * cfg_.grid.size_z_m;
  if ((may_move && far) || !grid_.inWindow(p_world_m)) grid_.recenter(p_world_m);
}

void TrajectoryServer::insertScan(const Eigen::Vector3d& sensor_origin_world_m,
                                  const std::vector<Eigen::Vector3f>& points_world_m) {
  if (!sensor_origin_world_m.allFinite()) {
    message_ = "scan rejected: non-finite sensor origin";
    return;
  }
  followWith(sensor_origin_world_m, true);
  std::vector<Eigen::Vector3d> points;
  points.reserve(points_world_m.size());
  size_t skipped = 0;
  for (const auto& p : points_world_m) {
    if (p.allFinite())
      points.push_back(p.cast<double>());
    else
      ++skipped;
  }
  if (skipped > 0) message_ = "scan: skipped " + std::to_string(skipped) + " non-finite points";
  grid_.insertScan(sensor_origin_world_m, points);

  const Trajectory* current = track_.current();
  if (goal_ && current && !stopping_ && last_update_s_) {
    const double t_from = std::max(0.0, *last_update_s_ - track_.currentStart_s());
    const double t_hit = LocalPlanner::firstCollisionTime(
        *current, grid_, t_from, cfg_.collision_check_horizon_s, cfg_.collision_check_clearance_m);
    if (t_hit >= 0.0) {
      collision_predicted_ = true;
      message_ = "collision predicted at " + vecString(current->position(t_hit)) + " in " +
                 std::to_string(t_hit - t_from) + " s";
    }
  }
}

ServerEvent TrajectoryServer::setGoal(const Eigen::Vector3d& goal_world_m,
                                      std::optional<Eigen::Vector3d> look_at_world_m,
                                      double time_s) {
  if (!goal_world_m.allFinite() || (look_at_world_m && !look_at_world_m->allFinite()) ||
      !std::isfinite(time_s)) {
    message_ = "goal rejected: non-finite goal " + vecString(goal_world_m) +
               (look_at_world_m ? ", look-at " + vecString(*look_at_world_m) : std::string()) +
               " or time";
    return ServerEvent::kRejectedInput;
  }
  constexpr double kSameGoal_m = 1e-6;
  if (requested_goal_ && (goal_world_m - *requested_goal_).norm() <= kSameGoal_m)
    return ServerEvent::kSameGoal;
  requested_goal_ = goal_world_m;
  // A goal elsewhere is a new question: the waits for the failed one do not apply to it.
  if (failed_goal_ && (goal_world_m - *failed_goal_).norm() > cfg_.new_question_distance_m) {
    failed_plans_ = 0;
    goal_failed_plans_ = 0;
  }
  // Another goal gets its own report; a nearby one inherits the failures counted so far (the
  // same unreachable place, asked again a little to the side).
  if (goal_failure_ && (goal_world_m - goal_failure_->goal_world_m).norm() > 1e-3)
    goal_given_up_ = false;
  goal_ = goal_world_m;
  look_at_ = look_at_world_m;
  new_goal_ = true;
  message_ = "new goal " + vecString(goal_world_m);
  return ServerEvent::kNone;
}

void TrajectoryServer::clearGoal(double time_s) {
  goal_.reset();
  look_at_.reset();
  requested_goal_.reset();
  new_goal_ = false;
  retry_at_s_.reset();
  collision_predicted_ = false;
  const std::optional<ReferenceSample> ref = referenceAt(time_s);
  if (!ref || !std::isfinite(time_s)) return;
  install(emergencyStop(ref->p_world_m, ref->v_world_mps, holdDecel(), ref->yaw_rad), time_s);
  message_ = "goal cleared: holding";
}

double TrajectoryServer::holdDecel() const {
  return cfg_.planner.emergency_decel_mps2 > 0.0 ? cfg_.planner.emergency_decel_mps2
                                                 : cfg_.planner.optimizer.a_max_mps2;
}

void TrajectoryServer::holdAlongPath(double time_s) {
  if (track_.holding() || !std::isfinite(time_s)) return;
  const std::optional<ReferenceSample> ref = track_.unwarpedAt(time_s);
  if (!ref) return;
  // Decelerating at a along the path from speed v takes v / a.
  track_.holdAlongPath(time_s, ref->v_world_mps.norm() / holdDecel());
  message_ = "odometry lost: stopping along the current trajectory";
}

void TrajectoryServer::resumeFromHold(double time_s) {
  if (!track_.holding() || !std::isfinite(time_s)) return;
  const std::optional<ReferenceSample> ref = referenceAt(time_s);
  track_.endHold();
  if (ref) {
    install(emergencyStop(ref->p_world_m, ref->v_world_mps, holdDecel(), ref->yaw_rad), time_s);
    track_.dropPrevious();  // the warped reference is gone: nothing before time_s to blend from
  }
  if (goal_) new_goal_ = true;
  message_ = "odometry back: replanning from the held reference";
}

ReferenceSample TrajectoryServer::sample(double time_s) const {
  if (!std::isfinite(time_s)) return {};
  return referenceAt(time_s).value_or(ReferenceSample{});
}

void TrajectoryServer::install(Trajectory traj, double start_s) {
  track_.install(std::move(traj), start_s);
}

ServerEvent TrajectoryServer::update(double time_s, const VehicleState& state) {
  if (!std::isfinite(time_s) || !state.p_world_m.allFinite() || !state.v_world_mps.allFinite() ||
      !state.a_world_mps2.allFinite() || !std::isfinite(state.yaw_rad)) {
    message_ = "update rejected: non-finite time or vehicle state";
    return ServerEvent::kRejectedInput;
  }
  last_update_s_ = time_s;
  if (!goal_ || track_.holding()) return ServerEvent::kNone;  // resumeFromHold() ends it

  std::string reason;
  if (new_goal_) {
    reason = "new goal";
  } else if (collision_predicted_) {
    reason = "collision predicted";
  } else if (retry_at_s_ && time_s >= *retry_at_s_) {
    reason = "retry after a failed plan";
  } else if (const Trajectory* current = track_.current()) {
    const double remaining_s = track_.currentStart_s() + current->duration() - time_s;
    const Eigen::Vector3d end_m = current->position(current->duration());
    // A goal moved out of an obstacle counts as reached at its substitute; a goal beyond the
    // window does not (the window follows the vehicle and the next plan gets closer).
    const bool ends_at_goal =
        (end_m - *goal_).norm() <= cfg_.goal_reached_m ||
        (last_plan_ && last_plan_->ok() && last_plan_->goal_adjusted && grid_.inWindow(*goal_));
    if (!stopping_ && ends_at_goal && remaining_s <= 0.0 &&
        (state.p_world_m - end_m).norm() <= cfg_.goal_reached_m) {
      goal_.reset();
      look_at_.reset();
      message_ = "goal reached at " + vecString(end_m);
      return ServerEvent::kGoalReached;
    }
    if (!ends_at_goal && remaining_s < cfg_.replan_horizon_remaining_s)
      reason = "horizon running out";
    else if (time_s - last_replan_s_ >= cfg_.replan_period_s &&
             (stopping_ || !ends_at_goal || remaining_s > cfg_.replan_horizon_remaining_s))
      reason = stopping_ ? "retry after emergency stop" : "replan period";
  } else {
    reason = "no trajectory";
  }
  if (reason.empty()) return ServerEvent::kNone;
  // After failed plans, wait before trying again (doubling, up to max_retry_backoff_s), whatever
  // asks for it, except a predicted collision: a failing search floods the whole window each
  // time (seen: 80 % of a core in A* behind a door the vehicle could not pass, asked again on
  // every new goal and every update once the stop had run out).
  if (failed_plans_ > 0 && !collision_predicted_) {
    const double backoff = std::min(cfg_.max_retry_backoff_s, cfg_.retry_after_failed_plan_s *
                                                                  std::pow(2.0, failed_plans_ - 1));
    if (time_s - last_replan_s_ < backoff - 1e-9) return ServerEvent::kNone;
  }
  return replan(time_s, state, reason);
}

ServerEvent TrajectoryServer::replan(double time_s, const VehicleState& state,
                                     const std::string& reason) {
  new_goal_ = false;
  retry_at_s_.reset();
  const bool collision = collision_predicted_;
  collision_predicted_ = false;
  last_replan_s_ = time_s;

  PlanRequest req;
  double start_s = time_s;
  const std::optional<ReferenceSample> now = referenceAt(time_s);
  const bool tracking =
      now && (now->p_world_m - state.p_world_m).norm() <= cfg_.max_tracking_error_m;
  if (tracking) {
    start_s = time_s + cfg_.plan_from_future_s;
    const ReferenceSample ref = *referenceAt(start_s);
    req.p_world_m = ref.p_world_m;
    req.v_world_mps = ref.v_world_mps;
    req.a_world_mps2 = ref.a_world_mps2;
    req.yaw_rad = ref.yaw_rad;
    req.yaw_rate_radps = ref.yaw_rate_radps;
  } else {
    req.p_world_m = state.p_world_m;
    req.v_world_mps = state.v_world_mps;
    req.a_world_mps2 = state.a_world_mps2;
    req.yaw_rad = state.yaw_rad;
  }
  req.goal_world_m = *goal_;
  if (look_at_) {
    req.has_look_at = true;
    req.look_at_world_m = *look_at_;
  }
  // Without scans the window would not follow the vehicle toward a goal beyond it.
  followWith(req.p_world_m, !grid_.inWindow(req.p_world_m) || !grid_.inWindow(*goal_));

  PlanResult result = planner_.plan(grid_, req);
  ++replans_;
  failed_plans_ = result.ok() ? 0 : failed_plans_ + 1;
  if (!result.ok()) failed_goal_ = *goal_;
  // The vehicle's own predicament (no escape from its start) and malformed requests say nothing
  // about the goal.
  if (result.ok())
    goal_failed_plans_ = 0;
  else if (result.status != PlanStatus::kStartInCollision &&
           result.status != PlanStatus::kBadRequest)
    ++goal_failed_plans_;
  if (goal_failed_plans_ >= cfg_.give_up_after_failed_plans && !goal_given_up_) {
    goal_given_up_ = true;
    GoalFailure f;
    f.sequence = goal_failure_ ? goal_failure_->sequence + 1 : 1;
    f.goal_world_m = *goal_;
    f.time_s = time_s;
    f.failed_plans = goal_failed_plans_;
    f.status = result.status;
    f.message = std::string(toString(result.status)) + ": " + result.message;
    goal_failure_ = std::move(f);
  }
  if (result.ok()) {
    install(result.trajectory, start_s);
    stopping_ = false;
    message_ = "replanned (" + reason + ")" + (result.goal_adjusted ? ", goal adjusted" : "");
    last_plan_ = std::move(result);
    return ServerEvent::kReplanned;
  }
  message_ = "plan failed (" + reason + "): " + std::string(toString(result.status)) + ": " +
             result.message;
  if (!collision && tracking && !stopping_ && track_.current() && !track_.current()->empty()) {
    retry_at_s_ = time_s + cfg_.retry_after_failed_plan_s;
    message_ += "; keeping the current trajectory (no collision predicted on it)";
    last_plan_ = std::move(result);
    return ServerEvent::kPlanFailedKeptCourse;
  }
  // Already braking and nothing new threatens the stop: keep it, the reference stays smooth.
  const bool keep_stop = stopping_ && !collision && tracking;
  if (!keep_stop && !result.trajectory.empty()) install(result.trajectory, start_s);
  last_plan_ = std::move(result);
  if (keep_stop) return ServerEvent::kNone;
  stopping_ = true;
  return ServerEvent::kEmergencyStop;
}

}  // namespace efs::traj
