// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/simulator.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "efs_common/config_check.h"

namespace efs::sim {
namespace {

/// Independent, reproducible seeds for each random stream from the one configured seed, so that
/// enabling LiDAR noise does not change the odometry noise and vice versa (splitmix64).
uint64_t streamSeed(uint64_t seed, uint64_t stream) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace

void SimulatorConfig::validate() const {
  requireInRange("physics_rate_hz", physics_rate_hz, 200.0, 20000.0);
  requireInRange("odometry_rate_hz", odometry_rate_hz, 1.0, physics_rate_hz);
  requireInRange("vehicle_radius_m", vehicle_radius_m, 0.01, 5.0);
  requireThat(initial_position_m.allFinite(), "initial_position_m", "must be finite");
  requireInRange("initial_yaw_rad", initial_yaw_rad, -2.0 * M_PI, 2.0 * M_PI);
  requireInRange("coverage_log_period_s", coverage_log_period_s, 0.01, 1e4);
  quadrotor.validate();
  lidar.validate();
  odometry.validate();
  coverage.validate();
  // RK4 on the rotor lag stays accurate only if a physics step is short against it.
  requireThat(quadrotor.rotor_time_constant_s * physics_rate_hz >= 2.0, "rotor_time_constant_s",
              "must be at least 2 physics steps (raise physics_rate_hz or the time constant)");
}

Simulator::Simulator(const WorldGeometry& world, const SimulatorConfig& config)
    : world_(world),
      config_((config.validate(), config)),
      dt_phys_s_(1.0 / config.physics_rate_hz),
      quad_(config.quadrotor),
      odom_model_(config.odometry, streamSeed(config.seed, 1)) {
  const Eigen::Vector3d& p0 = config_.initial_position_m;
  if (!world_.bounds().contains(p0)) {
    std::ostringstream os;
    os << "parameter 'initial_position_m' = (" << p0.transpose()
       << ") lies outside the world bounds";
    throw ConfigError(os.str());
  }
  if (world_.collides(p0, config_.vehicle_radius_m)) {
    std::ostringstream os;
    os << "parameter 'initial_position_m' = (" << p0.transpose()
       << ") is inside an obstacle (vehicle_radius_m " << config_.vehicle_radius_m << ")";
    throw ConfigError(os.str());
  }
  QuadrotorState s0;
  s0.p_world_m = p0;
  s0.q_world_body =
      Eigen::Quaterniond(Eigen::AngleAxisd(config_.initial_yaw_rad, Eigen::Vector3d::UnitZ()));
  // Start in hover: rotors already spinning at the hover thrust.
  s0.thrust_N = config_.quadrotor.mass_kg * config_.quadrotor.gravity_m_s2;
  quad_ = QuadrotorDynamics(config_.quadrotor, s0);
  if (config_.lidar_enabled) {
    lidar_ = std::make_unique<LivoxLidar>(config_.lidar, streamSeed(config_.seed, 0));
  }
  latest_odom_ = odom_model_.measure(quad_.state(), 0.0);
  odom_seq_ = 1;
  next_odom_index_ = 1;
  logCoverage(0.0);
  next_log_index_ = 1;
}

void Simulator::setCoverageGroundTruth(const VoxelKeySet& surface_keys) {
  coverage_ = std::make_unique<Coverage>(config_.coverage, surface_keys);
}

CommandStatus Simulator::setCommand(const SO3Command& cmd) {
  CommandStatus s = quad_.setCommand(cmd);
  if (!s.accepted) {
    ++rejected_commands_;
    last_rejection_ = s.reason;
  }
  return s;
}

CommandStatus Simulator::setCommand(const AttitudeTargetCommand& cmd) {
  CommandStatus s = quad_.setCommand(cmd);
  if (!s.accepted) {
    ++rejected_commands_;
    last_rejection_ = s.reason;
  }
  return s;
}

void Simulator::step(double dt_s) {
  if (!(dt_s > 0.0)) return;
  advanceTo(requested_time_s_ + dt_s);
}

void Simulator::advanceTo(double t_s) {
  if (!std::isfinite(t_s) || t_s <= requested_time_s_) return;
  requested_time_s_ = t_s;
  const double n = std::floor(t_s * config_.physics_rate_hz + 1e-6);
  if (n <= static_cast<double>(steps_)) return;
  const auto n_target = static_cast<uint64_t>(n);
  while (steps_ < n_target) physicsStep();
}

Eigen::Isometry3d Simulator::T_world_sensor() const {
  const QuadrotorState& s = quad_.state();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(s.p_world_m + s.q_world_body * config_.lidar.t_body_sensor_m);
  T.rotate(s.q_world_body * config_.lidar.q_body_sensor());
  return T;
}

void Simulator::physicsStep() {
  const double t_new = static_cast<double>(steps_ + 1) * dt_phys_s_;
  if (!collision_) {
    const QuadrotorState before = quad_.state();
    quad_.step(dt_phys_s_);
    const Eigen::Vector3d p1 = quad_.state().p_world_m;
    // Check the swept segment in sub-steps shorter than the radius so that nothing thin is
    // passed through at speed.
    const double len = (p1 - before.p_world_m).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(len / (0.25 * config_.vehicle_radius_m))));
    for (int i = 1; i <= n; ++i) {
      const Eigen::Vector3d p = before.p_world_m + (p1 - before.p_world_m) * (double(i) / n);
      if (!std::isfinite(len) || world_.collides(p, config_.vehicle_radius_m)) {
        CollisionReport r;
        r.stamp_s = t_new;
        r.position_m = before.p_world_m;
        r.attempted_position_m = p;
        collision_ = r;
        QuadrotorState stopped = before;
        stopped.v_world_m_s.setZero();
        stopped.omega_body_rad_s.setZero();
        quad_.setState(stopped);
        break;
      }
    }
    if (!collision_) travelled_m_ += len;
  }
  ++steps_;
  odom_model_.advanceDrift(dt_phys_s_);
  castLidarUpTo(t_new);
  const double odom_period = 1.0 / config_.odometry_rate_hz;
  if (static_cast<double>(next_odom_index_) * odom_period <= t_new + 1e-9) {
    latest_odom_ = odom_model_.measure(quad_.state(), t_new);
    ++odom_seq_;
    while (static_cast<double>(next_odom_index_) * odom_period <= t_new + 1e-9) ++next_odom_index_;
  }
  if (static_cast<double>(next_log_index_) * config_.coverage_log_period_s <= t_new + 1e-9) {
    logCoverage(t_new);
    while (static_cast<double>(next_log_index_) * config_.coverage_log_period_s <= t_new + 1e-9) {
      ++next_log_index_;
    }
  }
}

void Simulator::castLidarUpTo(double t_s) {
  if (!lidar_) return;
  const LivoxScanPattern& pattern = lidar_->pattern();
  const uint64_t k_target = pattern.firstPointAtOrAfter(t_s);
  const double frame_period = 1.0 / config_.lidar.frame_rate_hz;
  const QuadrotorState& s = quad_.state();
  const Eigen::Vector3d origin = s.p_world_m + s.q_world_body * config_.lidar.t_body_sensor_m;
  const Eigen::Isometry3d& T_est = odom_model_.T_est_world();
  const bool drift = !T_est.isApprox(Eigen::Isometry3d::Identity(), 0.0);
  const Eigen::Isometry3f T_est_f = T_est.cast<float>();
  while (next_point_ < k_target) {
    const double t_frame_end = static_cast<double>(frame_index_ + 1) * frame_period;
    const uint64_t k_frame_end = pattern.firstPointAtOrAfter(t_frame_end);
    const uint64_t k_stop = std::min(k_target, k_frame_end);
    batch_.points_world.clear();
    batch_.surface_world.clear();
    batch_.dirs_world.clear();
    rays_cast_ += lidar_->cast(world_, next_point_, k_stop, s.p_world_m, s.q_world_body, &batch_);
    if (coverage_) coverage_->observe(origin, batch_.surface_world, batch_.dirs_world);
    auto& pts = building_scan_.points_world;
    if (drift) {
      for (const auto& p : batch_.points_world) pts.push_back(T_est_f * p);
    } else {
      pts.insert(pts.end(), batch_.points_world.begin(), batch_.points_world.end());
    }
    next_point_ = k_stop;
    if (k_stop == k_frame_end) {
      building_scan_.seq = frame_index_ + 1;
      building_scan_.stamp_start_s = static_cast<double>(frame_index_) * frame_period;
      building_scan_.stamp_end_s = t_frame_end;
      std::swap(latest_scan_, building_scan_);
      building_scan_.points_world.clear();
      ++frame_index_;
    }
  }
}

void Simulator::logCoverage(double t_s) {
  coverage_log_.push_back({t_s, coverage_ ? coverage_->fraction() : 0.0, travelled_m_});
}

}  // namespace efs::sim
