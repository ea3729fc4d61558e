// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/odometry_model.h"

#include <cmath>

#include "efs_common/config_check.h"

namespace efs::sim {

void OdometryNoiseConfig::validate() const {
  requireInRange("position_noise_std_m", position_noise_std_m, 0.0, 10.0);
  requireInRange("orientation_noise_std_rad", orientation_noise_std_rad, 0.0, 1.0);
  requireInRange("velocity_noise_std_m_s", velocity_noise_std_m_s, 0.0, 10.0);
  requireInRange("angular_velocity_noise_std_rad_s", angular_velocity_noise_std_rad_s, 0.0, 10.0);
  requireInRange("position_drift_std_m_per_sqrt_s", position_drift_std_m_per_sqrt_s, 0.0, 10.0);
  requireInRange("yaw_drift_std_rad_per_sqrt_s", yaw_drift_std_rad_per_sqrt_s, 0.0, 1.0);
}

OdometryModel::OdometryModel(const OdometryNoiseConfig& config, uint64_t seed)
    : config_((config.validate(), config)), rng_(seed) {}

Eigen::Vector3d OdometryModel::gauss3() {
  const double x = n01_(rng_), y = n01_(rng_), z = n01_(rng_);
  return {x, y, z};
}

void OdometryModel::advanceDrift(double dt_s) {
  if (!(dt_s > 0.0)) return;
  const double sq = std::sqrt(dt_s);
  bool changed = false;
  if (config_.position_drift_std_m_per_sqrt_s > 0.0) {
    drift_p_m_ += config_.position_drift_std_m_per_sqrt_s * sq * gauss3();
    changed = true;
  }
  if (config_.yaw_drift_std_rad_per_sqrt_s > 0.0) {
    drift_yaw_rad_ += config_.yaw_drift_std_rad_per_sqrt_s * sq * n01_(rng_);
    changed = true;
  }
  if (changed) {
    T_est_world_ = Eigen::Isometry3d::Identity();
    T_est_world_.translate(drift_p_m_);
    T_est_world_.rotate(Eigen::AngleAxisd(drift_yaw_rad_, Eigen::Vector3d::UnitZ()));
  }
}

Odometry OdometryModel::measure(const QuadrotorState& truth, double stamp_s) {
  Odometry o;
  o.stamp_s = stamp_s;
  const Eigen::Quaterniond q_est_world(T_est_world_.rotation());
  o.p_world_m = T_est_world_ * truth.p_world_m;
  o.q_world_body = q_est_world * truth.q_world_body;
  o.v_world_m_s = q_est_world * truth.v_world_m_s;
  o.omega_body_rad_s = truth.omega_body_rad_s;
  if (config_.position_noise_std_m > 0.0) o.p_world_m += config_.position_noise_std_m * gauss3();
  if (config_.orientation_noise_std_rad > 0.0) {
    const Eigen::Vector3d e = config_.orientation_noise_std_rad * gauss3();
    o.q_world_body =
        (o.q_world_body * Eigen::Quaterniond(Eigen::AngleAxisd(
                              e.norm(), e.norm() > 0 ? e.normalized() : Eigen::Vector3d::UnitX())))
            .normalized();
  }
  if (config_.velocity_noise_std_m_s > 0.0)
    o.v_world_m_s += config_.velocity_noise_std_m_s * gauss3();
  if (config_.angular_velocity_noise_std_rad_s > 0.0) {
    o.omega_body_rad_s += config_.angular_velocity_noise_std_rad_s * gauss3();
  }
  return o;
}

}  // namespace efs::sim
