// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The in-process MARSIM-like simulator: quadrotor dynamics, a Livox LiDAR ray cast against a
// WorldGeometry, FAST-LIO2-shaped outputs (registered scan per frame, odometry), collision
// detection and ground-truth coverage. Time is simulated only: the caller steps it (a benchmark
// as fast as it can, the ROS node at its real-time factor). The world must outlive it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "marsim_worlds/coverage.h"
#include "marsim_worlds/livox_lidar.h"
#include "marsim_worlds/odometry_model.h"
#include "marsim_worlds/quadrotor_dynamics.h"
#include "marsim_worlds/world_geometry.h"

namespace efs::sim {

struct SimulatorConfig {
  double physics_rate_hz = 500.0;   ///< Dynamics and LiDAR batching rate (>= 200 Hz).
  double odometry_rate_hz = 100.0;  ///< FAST-LIO2 + EKF pose rate.
  double vehicle_radius_m = 0.25;   ///< Collision sphere.
  Eigen::Vector3d initial_position_m = Eigen::Vector3d::Zero();
  double initial_yaw_rad = 0.0;
  uint64_t seed = 1;
  bool lidar_enabled = true;
  QuadrotorConfig quadrotor;
  LivoxLidarConfig lidar;
  OdometryNoiseConfig odometry;
  CoverageConfig coverage;
  /// Period of the coverage / travelled-distance log.
  double coverage_log_period_s = 1.0;

  void validate() const;  ///< Throws efs::ConfigError naming the key.
};

/// One LiDAR frame, like FAST-LIO2's `cloud_registered`: points in the (estimated) world frame.
struct ScanFrame {
  uint64_t seq = 0;  ///< 1 for the first completed frame; 0 = none yet.
  double stamp_start_s = 0.0;
  double stamp_end_s = 0.0;
  std::vector<Eigen::Vector3f> points_world;
};

struct CollisionReport {
  double stamp_s = 0.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  ///< Where the vehicle was stopped.
  Eigen::Vector3d attempted_position_m = Eigen::Vector3d::Zero();  ///< The colliding state.
};

struct CoverageLogEntry {
  double stamp_s = 0.0;
  double coverage_fraction = 0.0;
  double travelled_distance_m = 0.0;
};

class Simulator {
 public:
  /// Throws efs::ConfigError for a bad config or a start pose that collides or lies outside the
  /// world's bounds (key `initial_position_m`).
  Simulator(const WorldGeometry& world, const SimulatorConfig& config);

  /// Ground-truth surface voxels for coverage; without it coverage() is null.
  void setCoverageGroundTruth(const VoxelKeySet& surface_keys);

  CommandStatus setCommand(const SO3Command& cmd);
  CommandStatus setCommand(const AttitudeTargetCommand& cmd);
  /// Rejected commands so far (the latest reason is kept).
  uint64_t rejectedCommands() const { return rejected_commands_; }
  const std::string& lastRejection() const { return last_rejection_; }

  /// Advances the requested time by `dt_s` and runs the physics steps due by then (the last step
  /// at or before it); requests shorter than a physics step accumulate, so no time is lost.
  void step(double dt_s);
  /// Runs the physics steps due by `t_s` (never goes back).
  void advanceTo(double t_s);
  double time_s() const { return static_cast<double>(steps_) * dt_phys_s_; }
  uint64_t physicsSteps() const { return steps_; }

  const ScanFrame& latestScan() const { return latest_scan_; }
  const Odometry& latestOdometry() const { return latest_odom_; }
  uint64_t odometrySeq() const { return odom_seq_; }
  const QuadrotorState& groundTruth() const { return quad_.state(); }
  /// Ideal body accelerometer (specific force, body frame) at the current time.
  Eigen::Vector3d imuSpecificForceBody() const { return quad_.specificForceBody(); }
  /// Sensor pose in the true world frame (for a TF tree or a test).
  Eigen::Isometry3d T_world_sensor() const;
  const Eigen::Isometry3d& T_est_world() const { return odom_model_.T_est_world(); }

  bool collided() const { return collision_.has_value(); }
  const std::optional<CollisionReport>& collision() const { return collision_; }

  const Coverage* coverage() const { return coverage_.get(); }
  const std::vector<CoverageLogEntry>& coverageLog() const { return coverage_log_; }
  double travelledDistance_m() const { return travelled_m_; }
  uint64_t raysCast() const { return rays_cast_; }

  const SimulatorConfig& config() const { return config_; }

 private:
  void physicsStep();
  void castLidarUpTo(double t_s);
  void logCoverage(double t_s);

  const WorldGeometry& world_;
  SimulatorConfig config_;
  double dt_phys_s_;
  uint64_t steps_ = 0;
  double requested_time_s_ = 0.0;
  QuadrotorDynamics quad_;
  std::unique_ptr<LivoxLidar> lidar_;
  OdometryModel odom_model_;
  std::unique_ptr<Coverage> coverage_;

  uint64_t next_point_ = 0;   ///< Next LiDAR point index to cast.
  uint64_t frame_index_ = 0;  ///< Frame being assembled.
  LidarReturns batch_;
  ScanFrame building_scan_, latest_scan_;
  Odometry latest_odom_;
  uint64_t odom_seq_ = 0, next_odom_index_ = 0;
  std::optional<CollisionReport> collision_;
  std::vector<CoverageLogEntry> coverage_log_;
  uint64_t next_log_index_ = 0;
  double travelled_m_ = 0.0;
  uint64_t rays_cast_ = 0;
  uint64_t rejected_commands_ = 0;
  std::string last_rejection_;
};

}  // namespace efs::sim
