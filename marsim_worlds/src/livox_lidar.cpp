// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/livox_lidar.h"

#include <cmath>

#include "efs_common/config_check.h"

namespace efs::sim {

void LivoxLidarConfig::validate() const {
  pattern.validate();
  requireInRange("frame_rate_hz", frame_rate_hz, 1.0, 100.0);
  requireInRange("max_range_m", max_range_m, 0.5, 1000.0);
  requireInRange("min_range_m", min_range_m, 0.0, max_range_m);
  requireInRange("range_noise_std_m", range_noise_std_m, 0.0, 1.0);
  requireInRange("mount_roll_rad", mount_roll_rad, -M_PI, M_PI);
  requireInRange("mount_pitch_rad", mount_pitch_rad, -M_PI, M_PI);
  requireInRange("mount_yaw_rad", mount_yaw_rad, -M_PI, M_PI);
  requireThat(t_body_sensor_m.allFinite() && t_body_sensor_m.norm() <= 2.0, "t_body_sensor_m",
              "must be finite and within 2 m of the body origin");
}

Eigen::Quaterniond LivoxLidarConfig::q_body_sensor() const {
  return Eigen::Quaterniond(Eigen::AngleAxisd(mount_yaw_rad, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(mount_pitch_rad, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(mount_roll_rad, Eigen::Vector3d::UnitX()))
      .normalized();
}

LivoxLidar::LivoxLidar(const LivoxLidarConfig& config, uint64_t seed)
    : config_(config),
      pattern_((config.validate(), config.pattern)),
      q_body_sensor_(config.q_body_sensor()),
      rng_(seed) {}

std::size_t LivoxLidar::cast(const WorldGeometry& world, uint64_t k_begin, uint64_t k_end,
                             const Eigen::Vector3d& p_world_body,
                             const Eigen::Quaterniond& q_world_body, LidarReturns* out) {
  if (k_end <= k_begin) return 0;
  const Eigen::Quaterniond q_world_sensor = q_world_body * q_body_sensor_;
  const Eigen::Vector3d origin = p_world_body + q_world_body * config_.t_body_sensor_m;
  dirs_scratch_.clear();
  pattern_.directions(k_begin, k_end, q_world_sensor.toRotationMatrix().cast<float>(),
                      &dirs_scratch_);
  world.castRays(origin, dirs_scratch_, config_.max_range_m, &ranges_scratch_);
  const Eigen::Vector3f o = origin.cast<float>();
  const float min_r = static_cast<float>(config_.min_range_m);
  const float max_r = static_cast<float>(config_.max_range_m);
  const float sigma = static_cast<float>(config_.range_noise_std_m);
  for (std::size_t i = 0; i < dirs_scratch_.size(); ++i) {
    const float r = ranges_scratch_[i];
    if (!(r >= min_r && r <= max_r)) continue;  // also drops NaN and kNoHit
    const Eigen::Vector3f& d = dirs_scratch_[i];
    const float r_noisy = sigma > 0.0f ? r + sigma * noise_(rng_) : r;
    out->surface_world.push_back(o + r * d);
    out->points_world.push_back(o + r_noisy * d);
    out->dirs_world.push_back(d);
  }
  return dirs_scratch_.size();
}

}  // namespace efs::sim
