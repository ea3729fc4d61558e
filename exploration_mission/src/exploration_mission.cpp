// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/exploration_mission.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "efs_common/config_check.h"
#include "efs_common/resource_usage.h"
#include "prior_guided_planner/prior_from_bundle.h"
#include "sketch_registration/prior_inputs.h"

namespace efs::mission {
namespace {

double yawOf(const Eigen::Quaterniond& q) {
  const Eigen::Vector3d x = q * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x());
}

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Adds the thread CPU time of its scope to a counter (the mission's compute budget per stage).
class CpuTimer {
 public:
  explicit CpuTimer(double& sink) : sink_(sink), start_(threadCpuSeconds()) {}
  ~CpuTimer() { sink_ += threadCpuSeconds() - start_; }
  CpuTimer(const CpuTimer&) = delete;
  CpuTimer& operator=(const CpuTimer&) = delete;

 private:
  double& sink_;
  double start_;
};

std::vector<planner::Hypothesis> toPlannerHypotheses(
    const std::vector<registration::Hypothesis>& in) {
  std::vector<planner::Hypothesis> out;
  out.reserve(in.size());
  for (const auto& h : in) {
    planner::Hypothesis p;
    p.id = h.id;
    p.T_world_sketch = h.T_world_sketch;
    p.confidence = h.confidence;
    out.push_back(p);
  }
  return out;
}

}  // namespace

const char* toString(MissionEnd end) {
  switch (end) {
    case MissionEnd::kRunning:
      return "running";
    case MissionEnd::kExplorationComplete:
      return "exploration complete";
    case MissionEnd::kCollision:
      return "collision";
    case MissionEnd::kTimeLimit:
      return "time limit";
  }
  return "?";
}

void MissionConfig::validate() const {
  session.validate();
  registration_map.validate();
  requireInRange("registration_rate_hz", registration_rate_hz, 0.01, 10.0);
  registration.validate();
  exploration.validate();
  mission_map.validate();
  trajectory.validate();
  controller.validate();
  requireInRange("control_rate_hz", control_rate_hz, 20.0, 1000.0);
  requireInRange("time_limit_s", time_limit_s, 1.0, 1e6);
  requireInRange("coverage_goal", coverage_goal, 0.01, 1.0);
  requireInRange("trajectory_log_period_s", trajectory_log_period_s, 0.01, 100.0);
  requireInRange("planner_scan_latency_s", planner_scan_latency_s, 0.0, 10.0);
  requireInRange("planner_update_rate_hz", planner_update_rate_hz, 0.0, 1000.0);
}

ExplorationMission::ExplorationMission(const MissionConfig& config,
                                       std::optional<MissionPrior> prior)
    : ExplorationMission(config, (config.validate(), sim::loadWorld(config.session.world)),
                         std::move(prior)) {}

ExplorationMission::ExplorationMission(const MissionConfig& config, sim::VoxelWorld world,
                                       std::optional<MissionPrior> prior)
    : config_(config),
      prior_(std::move(prior)),
      registration_map_(config.registration_map),
      registration_frames_(config.registration_rate_hz),
      mission_map_(config.mission_map),
      trajectory_(config.trajectory),
      controller_(config.controller),
      dt_control_s_(1.0 / config.control_rate_hz) {
  config_.validate();
  session_ = std::make_unique<sim::SimulationSession>(config_.session, std::move(world));
  // The planner keeps to the world's exploration box, as a user would give it.
  if (!config_.exploration.bounds_world_m) {
    config_.exploration.bounds_world_m = session_->world().bounds();
  }
  std::optional<planner::GuidepointPrior> guidepoints;
  if (prior_) {
    const registration::RegistrationPrior inputs =
        registration::registrationPriorFromBundle(prior_->bundle, config_.registration.d_gap_m);
    registration_ = std::make_unique<registration::SketchRegistration>(
        config_.registration, inputs.boundary_sketch_m, inputs.candidates_sketch_m);
    guidepoints = planner::guidepointPriorFromBundle(prior_->bundle);
  }
  exploration_ =
      std::make_unique<planner::ExplorationManager>(config_.exploration, std::move(guidepoints));
  const sim::StartPose& start = session_->start();
  hold_position_m_ = start.position_m;
  hold_yaw_rad_ = start.yaw_rad;
}

ExplorationMission::~ExplorationMission() = default;

const registration::RegistrationResult* ExplorationMission::registrationResult() const {
  return registration_ ? &registration_->result() : nullptr;
}

bool ExplorationMission::step() {
  if (log_.end != MissionEnd::kRunning) return false;
  sim::Simulator& sim = session_->simulator();
  {
    CpuTimer timer(log_.simulator_cpu_s);
    sim.step(dt_control_s_);
  }
  const double t = sim.time_s();
  if (sim.collided()) {
    const auto& c = *sim.collision();
    finish(MissionEnd::kCollision, "collision at (" + std::to_string(c.position_m.x()) + ", " +
                                       std::to_string(c.position_m.y()) + ", " +
                                       std::to_string(c.position_m.z()) + ")");
    return false;
  }
  if (observer_) observer_(sim);
  if (sim.latestScan().seq != last_scan_seq_) onScan();
  if (log_.end != MissionEnd::kRunning) return false;

  const sim::Odometry& odom = sim.latestOdometry();
  traj::VehicleState state;
  state.p_world_m = odom.p_world_m;
  state.v_world_mps = odom.v_world_m_s;
  state.yaw_rad = yawOf(odom.q_world_body);
  {
    CpuTimer timer(log_.trajectory_cpu_s);
    const traj::ServerEvent event = trajectory_.update(t, state);
    if (event == traj::ServerEvent::kReplanned) ++log_.replans;
    if (event == traj::ServerEvent::kEmergencyStop) ++log_.emergency_stops;
  }
  // As minco_traj_node publishes unreachable_goal to prior_guided_planner_node.
  if (const auto& failure = trajectory_.goalFailure();
      failure && failure->sequence != reported_goal_failure_) {
    reported_goal_failure_ = failure->sequence;
    GoalFailureRecord record;
    record.time_s = t;
    record.goal_world_m = failure->goal_world_m;
    record.viewpoint_world_m = exploration_->target().viewpoint_world_m;
    record.robot_world_m = odom.p_world_m;
    record.failed_plans = failure->failed_plans;
    record.status = failure->status;
    record.message = failure->message;
    {
      CpuTimer timer(log_.planner_cpu_s);
      record.outcome = exploration_->reportGoalUnreachable(failure->goal_world_m, t);
    }
    log_.goal_failures.push_back(std::move(record));
  }
  const traj::ReferenceSample sample = trajectory_.sample(t);
  control::FlatReference ref;
  ref.stamp_s = t;
  if (sample.valid) {
    ref.p_world_m = sample.p_world_m;
    ref.v_world_mps = sample.v_world_mps;
    ref.a_world_mps2 = sample.a_world_mps2;
    ref.j_world_mps3 = sample.j_world_mps3;
    ref.yaw_rad = sample.yaw_rad;
    ref.yaw_rate_radps = sample.yaw_rate_radps;
  } else {
    ref.p_world_m = hold_position_m_;  // before the first plan: hover where we started
    ref.yaw_rad = hold_yaw_rad_;
  }
  control::OdometryState o;
  o.stamp_s = odom.stamp_s;
  o.p_world_m = odom.p_world_m;
  o.v_world_mps = odom.v_world_m_s;
  o.q_world_body = odom.q_world_body;
  o.omega_body_radps = odom.omega_body_rad_s;
  if (t >= next_clearance_check_s_) {
    next_clearance_check_s_ = t + 0.1;
    log_.min_clearance_m = std::min(log_.min_clearance_m,
                                    session_->world().clearance(sim.groundTruth().p_world_m, 2.0));
  }
  if (sample.valid) {
    const double e = (sample.p_world_m - sim.groundTruth().p_world_m).norm();
    log_.max_tracking_error_m = std::max(log_.max_tracking_error_m, e);
    tracking_error_sq_sum_ += e * e;
    ++tracking_samples_;
  }
  const control::ControlOutput out = controller_.update(o, ref, t);
  sim::SO3Command cmd;
  cmd.force_world_N = out.so3.force_world_N;
  cmd.q_world_body_des = out.so3.orientation;
  cmd.omega_body_des_rad_s = out.so3.angular_velocity_body_radps;
  cmd.kR_Nm_per_rad = out.so3.kR;
  cmd.kOm_Nm_s_per_rad = out.so3.kOm;
  sim.setCommand(cmd);

  log_.flight_distance_m = sim.travelledDistance_m();
  if (sim.coverage()) {
    log_.coverage = sim.coverage()->fraction();
    if (!log_.time_to_coverage_goal_s && log_.coverage >= config_.coverage_goal) {
      log_.time_to_coverage_goal_s = t;
    }
  }
  if (t >= next_trajectory_log_s_) {
    const auto& gt = sim.groundTruth();
    log_.trajectory.push_back({t, gt.p_world_m, gt.v_world_m_s.norm()});
    next_trajectory_log_s_ = t + config_.trajectory_log_period_s;
  }
  if (t >= config_.time_limit_s) {
    finish(MissionEnd::kTimeLimit,
           "time limit of " + std::to_string(config_.time_limit_s) + " s reached");
    return false;
  }
  return true;
}

void ExplorationMission::onScan() {
  sim::Simulator& sim = session_->simulator();
  const sim::ScanFrame& scan = sim.latestScan();
  last_scan_seq_ = scan.seq;
  const double t = sim.time_s();
  const Eigen::Vector3d sensor_m = sim.latestOdometry().p_world_m;
  {
    CpuTimer timer(log_.trajectory_cpu_s);
    trajectory_.insertScan(sensor_m, scan.points_world);
  }
  planner::RobotPose robot;
  robot.position_world_m = sensor_m;
  robot.yaw_rad = yawOf(sim.latestOdometry().q_world_body);
  robot.velocity_world_mps = sim.latestOdometry().v_world_m_s;
  const planner::ExplorationTarget* target = nullptr;
  {
    CpuTimer timer(log_.planner_cpu_s);
    // Without latency the scan goes in as it is: no copy of its points on every scan.
    if (config_.planner_scan_latency_s > 0.0)
      late_scans_.push_back({t, sensor_m, scan.points_world});
    else
      exploration_->insertScan(sensor_m, scan.points_world);
    while (!late_scans_.empty() &&
           late_scans_.front().time_s + config_.planner_scan_latency_s <= t + 1e-9) {
      exploration_->insertScan(late_scans_.front().origin_world_m, late_scans_.front().points);
      late_scans_.pop_front();
    }
    if (config_.record_map) {
      mission_map_.insertScan(sensor_m, scan.points_world);
      mission_map_.addPose(t, sensor_m, robot.yaw_rad);
    }
  }
  // The registration's map and frame on its own clock (lio_bridge and sketch_registration in the
  // ROS graph): inside the planner's, a frame's time was counted twice and the map's as planning.
  if (registration_) {
    {
      CpuTimer timer(log_.registration_cpu_s);
      registration_map_.insert(scan.points_world, sensor_m);
    }
    if (registration_frames_.due(t)) onRegistrationFrame(t);
  }
  if (config_.planner_update_rate_hz > 0.0) {
    if (t + 1e-9 < next_planner_update_s_) return;
    next_planner_update_s_ = t + 1.0 / config_.planner_update_rate_hz;
  }
  {
    CpuTimer timer(log_.planner_cpu_s);
    target = &exploration_->update(t, robot);
  }
  if (target->replanned) {
    ++log_.planner_cycles;
    if (plan_observer_) plan_observer_(t, sensor_m, *exploration_);
  }
  if (target->active_hypothesis_id) last_active_hypothesis_id_ = target->active_hypothesis_id;
  planner_state_ = planner::toString(target->state);
  // kStuck is transient (the manager gives up what it cannot reach): the vehicle holds its
  // trajectory and the next update looks again, as in the ROS graph.
  if (target->state == planner::ExplorationState::kFinished) {
    finish(MissionEnd::kExplorationComplete, target->message);
    return;
  }
  // As the node's timer does, every update hands the target on; the server takes only a new goal.
  if (target->has_goal) {
    CpuTimer timer(log_.trajectory_cpu_s);
    trajectory_.setGoal(target->goal_world_m, target->look_at_world_m, t);
  }
}

void ExplorationMission::onRegistrationFrame(double t_s) {
  CpuTimer timer(log_.registration_cpu_s);
  const Eigen::Vector3d robot_m = session_->simulator().latestOdometry().p_world_m;
  registration_map_.crop(robot_m);
  const std::vector<Eigen::Vector3f> map = registration_map_.points();
  registration::Points3d points;
  points.reserve(map.size());
  for (const auto& p : map) points.emplace_back(p.cast<double>());
  const registration::RegistrationResult& result = registration_->addFrame(t_s, robot_m, points);
  log_.registrations.push_back({t_s, result.status, result.hypotheses, result.message});
  exploration_->setHypotheses(toPlannerHypotheses(result.hypotheses));
}

void ExplorationMission::finish(MissionEnd end, const std::string& message) {
  const sim::Simulator& sim = session_->simulator();
  log_.end = end;
  log_.end_message = message;
  log_.end_time_s = sim.time_s();
  log_.flight_distance_m = sim.travelledDistance_m();
  log_.coverage_log = sim.coverageLog();
  if (tracking_samples_ > 0) {
    log_.rms_tracking_error_m = std::sqrt(tracking_error_sq_sum_ / tracking_samples_);
  }
  if (const sim::Coverage* coverage = sim.coverage()) {
    log_.coverage = coverage->fraction();
    log_.coverage_gaps = sim::coverageGaps(*coverage, session_->world());
  }
  const auto& gt = sim.groundTruth();
  log_.trajectory.push_back({sim.time_s(), gt.p_world_m, gt.v_world_m_s.norm()});
}

planner::SavedMissionMap ExplorationMission::saveMap(const std::string& directory) const {
  planner::MapRegistration reg;
  reg.hypotheses = exploration_->hypotheses();
  std::sort(reg.hypotheses.begin(), reg.hypotheses.end(),
            [](const planner::Hypothesis& a, const planner::Hypothesis& b) {
              return a.confidence > b.confidence;
            });
  reg.active_hypothesis_id = last_active_hypothesis_id_;
  return mission_map_.save(directory, exploration_->occupancy(), reg);
}

MissionProgress ExplorationMission::progress() const {
  MissionProgress p;
  p.time_s = session_->simulator().time_s();
  p.coverage = log_.coverage;
  p.flight_distance_m = log_.flight_distance_m;
  if (registration_) {
    const auto& hyps = registration_->result().hypotheses;
    p.hypotheses = hyps.size();
    if (!hyps.empty()) p.best_confidence = hyps.front().confidence;
    p.registration_status = registration::toString(registration_->result().status);
  }
  p.planner_state = planner_state_;
  return p;
}

const MissionLog& ExplorationMission::run(
    const std::function<void(const MissionProgress&)>& progress, double progress_period_s) {
  double next_progress_s = 0.0;
  while (step()) {
    if (progress && session_->simulator().time_s() >= next_progress_s) {
      progress(this->progress());
      next_progress_s += progress_period_s;
    }
  }
  if (progress) progress(this->progress());
  return log_;
}

}  // namespace efs::mission
