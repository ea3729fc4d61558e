// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// LIO-shaped odometry from the true state: white noise on each output plus a slow random-walk
// drift of the estimator's world frame (x, y, z, yaw), as a LiDAR-inertial odometry drifts. The
// drift is a transform T_est_world so that the registered scan and the odometry stay consistent
// with each other, as FAST-LIO2's `cloud_registered` and `Odometry` are.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <random>

#include "marsim_worlds/quadrotor_dynamics.h"

namespace efs::sim {

struct OdometryNoiseConfig {
  double position_noise_std_m = 0.0;
  double orientation_noise_std_rad = 0.0;  ///< Per axis, small-angle.
  double velocity_noise_std_m_s = 0.0;
  double angular_velocity_noise_std_rad_s = 0.0;
  /// Random-walk drift of the estimated frame: standard deviation after 1 s.
  double position_drift_std_m_per_sqrt_s = 0.0;
  double yaw_drift_std_rad_per_sqrt_s = 0.0;

  void validate() const;  ///< Throws efs::ConfigError naming the key.
};

/// Like nav_msgs/Odometry from FAST-LIO2: pose and linear velocity in the (estimated) world
/// frame, angular velocity in the body frame.
struct Odometry {
  double stamp_s = 0.0;
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_world_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d omega_body_rad_s = Eigen::Vector3d::Zero();
};

class OdometryModel {
 public:
  OdometryModel(const OdometryNoiseConfig& config, uint64_t seed);

  /// Advances the drift by `dt_s` (call with the simulator's physics steps).
  void advanceDrift(double dt_s);

  /// Odometry of the true state at `stamp_s`, with fresh white noise.
  Odometry measure(const QuadrotorState& truth, double stamp_s);

  /// The estimator's world frame relative to the true one (identity without drift).
  const Eigen::Isometry3d& T_est_world() const { return T_est_world_; }

 private:
  OdometryNoiseConfig config_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> n01_{0.0, 1.0};
  Eigen::Vector3d drift_p_m_ = Eigen::Vector3d::Zero();
  double drift_yaw_rad_ = 0.0;
  Eigen::Isometry3d T_est_world_ = Eigen::Isometry3d::Identity();
  Eigen::Vector3d gauss3();
};

}  // namespace efs::sim
