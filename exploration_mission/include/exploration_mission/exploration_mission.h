// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// One closed-loop exploration flown in-process, in simulated time, with the core classes the ROS
// graph wraps, wired as the nodes are (README, "Architecture"):
//   Simulator --scan, odometry--> LocalMap --0.2 Hz frames--> SketchRegistration --hypotheses-->
//   ExplorationManager --target--> TrajectoryServer --reference at 100 Hz--> Se3Controller
//   --SO3Command--> Simulator.
// Planning is instantaneous in simulated time (compute latency is not simulated); everything is
// deterministic for a given configuration. The mission ends when the planner reports that no
// viewpoint remains, on a collision, or at the time limit.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "exploration_mission/mission_config.h"
#include "exploration_mission/mission_prior.h"

namespace efs::mission {

enum class MissionEnd {
  kRunning,
  kExplorationComplete,  ///< the planner found no viewpoint left
  kCollision,            ///< the vehicle touched the world (a failed run)
  kTimeLimit,            ///< time_limit_s reached first
};
const char* toString(MissionEnd end);

/// One registration output, as the planner received it.
struct HypothesisRecord {
  double time_s = 0.0;
  registration::RegistrationStatus status = registration::RegistrationStatus::kTooFewFrames;
  std::vector<registration::Hypothesis> hypotheses;  ///< best first
  std::string message;                               ///< the registration's reason for status
};

struct TrajectoryRecord {
  double time_s = 0.0;
  Eigen::Vector3d position_world_m = Eigen::Vector3d::Zero();  ///< ground truth
  double speed_mps = 0.0;
};

/// A goal the local planner gave up on, and what the exploration planner made of it.
struct GoalFailureRecord {
  double time_s = 0.0;
  Eigen::Vector3d goal_world_m = Eigen::Vector3d::Zero();
  /// The planner's target viewpoint then (the goal lies on the way to it or along the tour).
  Eigen::Vector3d viewpoint_world_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d robot_world_m = Eigen::Vector3d::Zero();  ///< odometry when it gave up
  int failed_plans = 0;
  traj::PlanStatus status = traj::PlanStatus::kGoalUnreachable;  ///< of the last failed plan
  std::string message;  ///< the local planner's reason for that plan
  /// What the exploration planner made of it (kNotCurrent: it had moved on to another goal).
  planner::GoalRefusal outcome = planner::GoalRefusal::kNotCurrent;
};

/// What the mission did; filled as it flies.
struct MissionLog {
  MissionEnd end = MissionEnd::kRunning;
  std::string end_message;
  double end_time_s = 0.0;
  double flight_distance_m = 0.0;
  double coverage = 0.0;
  std::optional<double> time_to_coverage_goal_s;
  std::vector<sim::CoverageLogEntry> coverage_log;
  std::vector<TrajectoryRecord> trajectory;
  std::vector<HypothesisRecord> registrations;
  size_t replans = 0, emergency_stops = 0, planner_cycles = 0;
  std::vector<GoalFailureRecord> goal_failures;  ///< every goal the local planner gave up on
  /// Distance between the reference and the true position, over the flight (RMS set at the end).
  double max_tracking_error_m = 0.0, rms_tracking_error_m = 0.0;
  /// Closest the vehicle's centre came to the world's surface (sampled at 10 Hz, capped at 2 m;
  /// the simulator's collision radius is 0.25 m): the safety margin the flight kept.
  double min_clearance_m = 2.0;
  /// Thread CPU per component, each counted once: registration = its accumulated map (lio_bridge's
  /// work in the ROS graph) and its frames; planner = the exploration maps, the mission map and
  /// planning (until 2026-11-29 it also held the registration's, frames counted in both).
  double registration_cpu_s = 0.0, planner_cpu_s = 0.0, trajectory_cpu_s = 0.0;
  double simulator_cpu_s = 0.0;
  /// Where coverage fell short at the end (empty without ground truth).
  sim::CoverageGaps coverage_gaps;
};

/// A progress snapshot for a progress line.
struct MissionProgress {
  double time_s = 0.0;
  double coverage = 0.0;
  double flight_distance_m = 0.0;
  size_t hypotheses = 0;
  double best_confidence = 0.0;
  std::string registration_status;  ///< why there is no hypothesis yet, or "ok"
  std::string planner_state;
};

class ExplorationMission {
 public:
  /// `prior`: the sketch to fly with, or std::nullopt for a prior-free run. Throws
  /// efs::ConfigError naming the key for a bad configuration.
  ExplorationMission(const MissionConfig& config, std::optional<MissionPrior> prior);
  /// Same on a world the caller already loaded (moved in).
  ExplorationMission(const MissionConfig& config, sim::VoxelWorld world,
                     std::optional<MissionPrior> prior);
  ~ExplorationMission();

  /// Advances one control period; false once the mission has ended.
  bool step();
  /// Steps until the end; calls `progress` every `progress_period_s` of simulated time.
  const MissionLog& run(const std::function<void(const MissionProgress&)>& progress = {},
                        double progress_period_s = 10.0);

  /// Called after every control step with the simulator (e.g. to record its outputs to a bag).
  void setStepObserver(std::function<void(const sim::Simulator&)> observer) {
    observer_ = std::move(observer);
  }

  /// Called after every planning cycle with the simulated time, the robot position and the
  /// exploration planner (e.g. a PlanLog).
  void setPlanObserver(
      std::function<void(double, const Eigen::Vector3d&, const planner::ExplorationManager&)>
          observer) {
    plan_observer_ = std::move(observer);
  }

  const MissionLog& log() const { return log_; }
  MissionProgress progress() const;
  const sim::SimulationSession& session() const { return *session_; }
  const std::optional<MissionPrior>& prior() const { return prior_; }
  const MissionConfig& config() const { return config_; }
  /// The latest registration result (empty without a prior).
  const registration::RegistrationResult* registrationResult() const;
  /// Writes what the mission leaves behind into `directory` (planner::MissionMap::save: dense
  /// cloud, OctoMap, track, registration). Throws std::runtime_error naming a file it cannot write.
  planner::SavedMissionMap saveMap(const std::string& directory) const;
  /// The exploration planner's state (maps, frontiers, viewpoints, last plan), for diagnostics.
  const planner::ExplorationManager& explorationManager() const { return *exploration_; }
  /// The local planner's state (its occupancy window, current trajectory), for diagnostics.
  const traj::TrajectoryServer& trajectoryServer() const { return trajectory_; }

 private:
  void onScan();
  void onRegistrationFrame(double t_s);
  void finish(MissionEnd end, const std::string& message);

  MissionConfig config_;
  std::optional<MissionPrior> prior_;
  std::unique_ptr<sim::SimulationSession> session_;
  lio::LocalMap registration_map_;
  lio::FrameDecimator registration_frames_;
  std::unique_ptr<registration::SketchRegistration> registration_;
  std::unique_ptr<planner::ExplorationManager> exploration_;
  planner::MissionMap mission_map_;
  traj::TrajectoryServer trajectory_;
  control::Se3Controller controller_;
  MissionLog log_;
  struct LateScan {
    double time_s;
    Eigen::Vector3d origin_world_m;
    std::vector<Eigen::Vector3f> points;
  };
  /// Scans on their way to the planner (MissionConfig::planner_scan_latency_s).
  std::deque<LateScan> late_scans_;
  double next_planner_update_s_ = 0.0;
  uint64_t last_scan_seq_ = 0;
  double dt_control_s_;
  double next_trajectory_log_s_ = 0.0;
  double tracking_error_sq_sum_ = 0.0;
  size_t tracking_samples_ = 0;
  double next_clearance_check_s_ = 0.0;
  uint64_t reported_goal_failure_ = 0;  ///< sequence of the last GoalFailure passed on
  Eigen::Vector3d hold_position_m_ = Eigen::Vector3d::Zero();
  double hold_yaw_rad_ = 0.0;
  std::string planner_state_ = "waiting";
  std::optional<int> last_active_hypothesis_id_;  ///< the last one the guidance used
  std::function<void(const sim::Simulator&)> observer_;
  std::function<void(double, const Eigen::Vector3d&, const planner::ExplorationManager&)>
      plan_observer_;
};

}  // namespace efs::mission
