// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Livox-like non-repetitive scan patterns as tables of unit directions in the sensor frame
// (x forward, z up), one entry per point in firing order. Point k fires at k / point_rate_hz.
//
// Mid-360: the directions follow a 2D Kronecker (R2, plastic-number) sequence over azimuth and
// sin(elevation), so that any window of consecutive points is spread uniformly over the solid
// angle of the field of view and no two frames repeat; every table period the whole table is
// turned about the sensor z axis by the golden angle so that the pattern never repeats.
// Avia: a rosette drawn by two counter-rotating prisms with an irrational speed ratio, six lasers
// interleaved, filling an ellipse of 70.4 x 77.2 deg around the sensor x axis.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace efs::sim {

enum class LivoxModel { kMid360, kAvia };

struct LivoxPatternConfig {
  LivoxModel model = LivoxModel::kMid360;
  double point_rate_hz = 200000.0;  ///< Mid-360: 200k points/s; the Avia is 240k.
  /// Mid-360 field of view: full azimuth, elevation band (sensor frame).
  double elevation_min_rad = -7.0 * M_PI / 180.0;
  double elevation_max_rad = 52.0 * M_PI / 180.0;
  /// Avia field of view (full angles, horizontal about sensor z, vertical about sensor y).
  double avia_fov_horizontal_rad = 70.4 * M_PI / 180.0;
  double avia_fov_vertical_rad = 77.2 * M_PI / 180.0;
  /// Mid-360: points are fired in azimuth order within blocks of this many (a sweep of the
  /// head); 1 keeps the raw low-discrepancy order. Frames and 1 s windows hold whole blocks.
  int sweep_block_points = 400;
  /// Length of the precomputed table. Longer costs memory (12 bytes per point).
  double table_period_s = 1.0;

  void validate() const;  ///< Throws efs::ConfigError naming the key.
  static LivoxPatternConfig mid360();
  static LivoxPatternConfig avia();
};

class LivoxScanPattern {
 public:
  explicit LivoxScanPattern(const LivoxPatternConfig& config);

  const LivoxPatternConfig& config() const { return config_; }
  std::size_t tableSize() const { return table_.size(); }

  /// Unit direction of point `k` (k counted from the sensor's start) in the sensor frame.
  Eigen::Vector3f direction(uint64_t k) const;

  /// Appends the directions of points [k_begin, k_end) to `dirs_sensor`, each rotated by
  /// `R_out_sensor` (pass R_world_sensor to get world-frame directions in one pass).
  void directions(uint64_t k_begin, uint64_t k_end, const Eigen::Matrix3f& R_out_sensor,
                  std::vector<Eigen::Vector3f>* dirs_out) const;

  /// Index of the first point fired at or after `t_s` (points fire at k / point_rate_hz).
  uint64_t firstPointAtOrAfter(double t_s) const;

 private:
  LivoxPatternConfig config_;
  std::vector<Eigen::Vector3f> table_;
  bool rotate_per_period_ = true;
};

}  // namespace efs::sim
