// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The stateful trajectory server of paper Sec. VI-E, shared by the ROS node and in-process
// missions: it owns the local grid (fed with registered scans), the current goal and the current
// trajectory, decides when to replan and samples the reference (PositionCommand content).
//
// Replanning policy, evaluated by update(time_s, state):
//   * a new goal, a collision predicted on the current trajectory by the last scan(s)
//     (within collision_check_horizon_s), the replan period elapsed, or the trajectory ending
//     sooner than replan_horizon_remaining_s while the goal is not reached;
//   * the plan starts from the reference at time_s + plan_from_future_s (the compute latency),
//     so p, v, a are continuous at the switch; the previous trajectory keeps being sampled until
//     then. Without a reference, or when the vehicle is farther than max_tracking_error_m from
//     it (a kick, a crash into the wall of reality), the plan starts from the vehicle state;
//   * a failed plan keeps the current trajectory when nothing threatens it (it was checked and
//     no collision is predicted on it) and retries after retry_after_failed_plan_s: a straight
//     brake from a curve can leave the checked path (seen: a cave wall touched after an
//     optimiser failure on a new goal). Otherwise (a predicted collision, lost tracking) it
//     switches to the planner's emergency stop (braking at the acceleration limit) once; while
//     stopping, later failures keep the same stop so the reference stays smooth;
//   * a goal that failed give_up_after_failed_plans consecutive plans is given up: goalFailure()
//     says so (once per goal), for the exploration planner to choose another target. The server
//     itself keeps the goal and keeps retrying (with backoff) until it gets a new one.
// Time is injected; nothing here reads a clock.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "minco_traj/local_grid.h"
#include "minco_traj/local_planner.h"
#include "minco_traj/reference_track.h"
#include "minco_traj/trajectory.h"

namespace efs::traj {

struct TrajectoryServerConfig {
  LocalPlannerConfig planner;
  LocalGridConfig grid;
  double replan_period_s = 1.0;             ///< replan at least this often while flying to a goal
  double replan_horizon_remaining_s = 0.5;  ///< replan when the trajectory ends sooner than this
  double collision_check_horizon_s = 2.0;   ///< collision prediction on each new scan
  /// An occupied cell centre this close to the trajectory ahead is a predicted collision:
  /// collision radius 0.25 m + half a cell + 0.05 m; below the corridor clearance, so a fresh
  /// plan never triggers it.
  double collision_check_clearance_m = 0.35;
  double goal_reached_m = 0.3;
  double plan_from_future_s = 0.05;   ///< start state sampled this far ahead (compute latency)
  double max_tracking_error_m = 1.0;  ///< farther from the reference: plan from the vehicle state
  double retry_after_failed_plan_s = 0.2;  ///< a failed plan that kept the course is retried then
  /// Consecutive failed plans wait retry_after_failed_plan_s * 2^(n-1) before the next one, at
  /// most this long (a predicted collision does not wait).
  double max_retry_backoff_s = 2.0;
  /// A new goal farther than this from the last one that failed starts without waiting.
  double new_question_distance_m = 2.0;
  /// After this many consecutive failed plans toward one goal (a vehicle stuck in a wall, or a
  /// request with a non-finite input, does not count), the goal is given up (goalFailure()).
  /// The exploration planner's own watchdog (no progress in 10 s) was the only other way out:
  /// seen in the garage, 30 s hovering 2.4 m from three viewpoints the global search reached
  /// through a gap the vehicle's clearance did not pass.
  int give_up_after_failed_plans = 3;
  /// The grid window follows the sensor in horizontal steps of this size (vertical: a quarter
  /// of the window height); recentring costs a pass over the window.
  double recenter_distance_m = 2.0;
  void validate() const;
};

enum class ServerEvent {
  kNone,
  kReplanned,
  kPlanFailedKeptCourse,  ///< the plan failed; the current, still clear trajectory is kept
  kEmergencyStop,
  kGoalReached,
  kRejectedInput,
  kSameGoal  ///< setGoal: the goal of the last request again, ignored
};
const char* toString(ServerEvent e);

struct VehicleState {
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_world_mps2 = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
};

/// A goal the server gave up on (give_up_after_failed_plans).
struct GoalFailure {
  uint64_t sequence = 0;  ///< 1, 2, ... for each goal given up: a consumer reports each once
  Eigen::Vector3d goal_world_m = Eigen::Vector3d::Zero();
  double time_s = 0.0;
  int failed_plans = 0;
  PlanStatus status = PlanStatus::kGoalUnreachable;  ///< of the last failed plan
  std::string message;                               ///< the last failed plan's reason
};

class TrajectoryServer {
 public:
  explicit TrajectoryServer(const TrajectoryServerConfig& config = {});
  const TrajectoryServerConfig& config() const { return cfg_; }

  /// One registered scan (world frame) and the sensor origin: local grid update (window
  /// recentred on the sensor) + collision prediction of the current trajectory -> replan flag.
  /// Non-finite points are skipped; a non-finite origin rejects the scan (lastMessage()).
  void insertScan(const Eigen::Vector3d& sensor_origin_world_m,
                  const std::vector<Eigen::Vector3f>& points_world_m);
  /// New target (look_at optional: where the sensor should point; the goal otherwise).
  /// Non-finite -> kRejectedInput with a message, the previous goal is kept. The goal of the
  /// last accepted request again (within 1e-6 m, until clearGoal) -> kSameGoal, nothing changes
  /// (its look-at point neither, as the mission always had it):
  /// the planner hands its target on at every update (10 Hz), and a repeat would replan and,
  /// once the goal was reached, send the vehicle back to it.
  ServerEvent setGoal(const Eigen::Vector3d& goal_world_m,
                      std::optional<Eigen::Vector3d> look_at_world_m, double time_s);
  /// Drops the goal and brakes to a hold from the current reference.
  void clearGoal(double time_s);
  /// Replans when due from the reference state at time_s (continuity), or from `state` when
  /// there is no valid reference yet. Non-finite time or state -> kRejectedInput.
  ServerEvent update(double time_s, const VehicleState& state);
  /// Reference at time_s; holds the end point after the trajectory ends.
  ReferenceSample sample(double time_s) const;

  /// Odometry lost: from time_s on the reference slows down *along the current trajectory* (its
  /// time is warped, its rate falling linearly from 1 to 0 at the emergency deceleration) and
  /// stops on it. The path was checked free; a straight-line brake from a curve can leave it
  /// (seen: a cave wall hit 2 s into a LIO dropout). Nothing is replanned meanwhile. No-op
  /// without a trajectory or when already holding.
  void holdAlongPath(double time_s);
  /// Odometry is back: the reference continues from the held state (a brake to rest if it was
  /// still moving) and the goal is replanned on the next update().
  void resumeFromHold(double time_s);
  bool holdingAlongPath() const { return track_.holding(); }

  /// The newest trajectory (nullptr before the first one) and its start time.
  const Trajectory* current() const { return track_.current(); }
  double currentStart_s() const { return track_.currentStart_s(); }
  /// Everything sample() reads: a copy samples the same reference on another thread.
  const ReferenceTrack& track() const { return track_; }
  /// The last planner result (nullptr before the first plan).
  const PlanResult* lastPlan() const { return last_plan_ ? &*last_plan_ : nullptr; }
  const LocalGrid& grid() const { return grid_; }
  LocalGrid& mutableGrid() { return grid_; }
  const std::optional<Eigen::Vector3d>& goal() const { return goal_; }
  bool stopping() const { return stopping_; }
  const std::string& lastMessage() const { return message_; }
  int replanCount() const { return replans_; }
  /// The last goal given up (give_up_after_failed_plans); std::nullopt before the first one.
  /// A new sequence number means a new failure; the goal may still be the current one.
  const std::optional<GoalFailure>& goalFailure() const { return goal_failure_; }

 private:
  /// Plans from the reference (or `state`) at time_s + plan_from_future_s.
  ServerEvent replan(double time_s, const VehicleState& state, const std::string& reason);
  void install(Trajectory traj, double start_s);
  /// Recentres the grid on p when p is outside the window, or when may_move and p is more than
  /// recenter_distance_m from the window centre.
  void followWith(const Eigen::Vector3d& p_world_m, bool may_move);
  std::optional<ReferenceSample> referenceAt(double time_s) const { return track_.at(time_s); }
  double holdDecel() const;

  TrajectoryServerConfig cfg_;
  LocalGrid grid_;
  LocalPlanner planner_;
  ReferenceTrack track_;
  std::optional<PlanResult> last_plan_;
  std::optional<Eigen::Vector3d> goal_, look_at_;
  std::optional<Eigen::Vector3d> requested_goal_;  ///< of the last request setGoal accepted
  bool new_goal_ = false;
  std::optional<double> retry_at_s_;  ///< a failed plan that kept the course is retried then
  bool collision_predicted_ = false;
  bool stopping_ = false;
  double last_replan_s_ = 0.0;
  std::optional<double> last_update_s_;
  int replans_ = 0;
  int failed_plans_ = 0;                        ///< consecutive
  std::optional<Eigen::Vector3d> failed_goal_;  ///< the goal of the last failed plan
  int goal_failed_plans_ = 0;                   ///< consecutive, not counting a start in collision
  bool goal_given_up_ = false;                  ///< the current goal was reported in goal_failure_
  std::optional<GoalFailure> goal_failure_;
  std::string message_;
};

}  // namespace efs::traj
