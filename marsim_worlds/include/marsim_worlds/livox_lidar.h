// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// A Livox LiDAR mounted on the vehicle: scan pattern, extrinsics, range limits and noise. Casting
// one batch of consecutive points against a world gives world-frame returns, which is how the
// simulator builds a frame while the vehicle moves (each batch uses the pose at its own time,
// the way FAST-LIO2 deskews a scan).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <random>
#include <vector>

#include "marsim_worlds/livox_scan_pattern.h"
#include "marsim_worlds/world_geometry.h"

namespace efs::sim {

struct LivoxLidarConfig {
  LivoxPatternConfig pattern;
  double frame_rate_hz = 10.0;
  double max_range_m = 40.0;
  double min_range_m = 0.1;  ///< Mid-360 blind zone.
  double range_noise_std_m = 0.02;
  /// Mounting in the body frame (REP 103: x forward, z up). Positive pitch tilts the sensor's
  /// forward axis down; the paper's field platform has the Mid-360 pitched by 15 deg.
  double mount_roll_rad = 0.0;
  double mount_pitch_rad = 15.0 * M_PI / 180.0;
  double mount_yaw_rad = 0.0;
  Eigen::Vector3d t_body_sensor_m = Eigen::Vector3d(0.1, 0.0, 0.05);

  void validate() const;  ///< Throws efs::ConfigError naming the key.
  Eigen::Quaterniond q_body_sensor() const;
};

/// One batch of returns. `points_world` holds one point per valid return (noisy range),
/// `surface_world` the same returns without noise (for ground-truth coverage).
struct LidarReturns {
  std::vector<Eigen::Vector3f> points_world;
  std::vector<Eigen::Vector3f> surface_world;
  std::vector<Eigen::Vector3f> dirs_world;  ///< Unit ray directions of the returns.
};

class LivoxLidar {
 public:
  LivoxLidar(const LivoxLidarConfig& config, uint64_t seed);

  const LivoxLidarConfig& config() const { return config_; }
  const LivoxScanPattern& pattern() const { return pattern_; }

  /// Casts points [k_begin, k_end) from the body pose (p_world_body, q_world_body) and appends
  /// the valid returns to `out`. Returns the number of rays cast.
  std::size_t cast(const WorldGeometry& world, uint64_t k_begin, uint64_t k_end,
                   const Eigen::Vector3d& p_world_body, const Eigen::Quaterniond& q_world_body,
                   LidarReturns* out);

 private:
  LivoxLidarConfig config_;
  LivoxScanPattern pattern_;
  Eigen::Quaterniond q_body_sensor_;
  std::mt19937_64 rng_;
  std::normal_distribution<float> noise_{0.0f, 1.0f};
  std::vector<Eigen::Vector3f> dirs_scratch_;
  std::vector<float> ranges_scratch_;
};

}  // namespace efs::sim
