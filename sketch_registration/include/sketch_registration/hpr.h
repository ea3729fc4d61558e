// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Hidden point removal for 2D point sets (the sketch boundary, or the LiDAR map projected onto
// the horizontal plane), seen from a viewpoint. The visible set is the star-convex polygon around
// the viewpoint: in every direction only the nearest boundary is kept. It is computed with a polar
// depth buffer whose bins are much finer than the descriptor's; every point is splatted over the
// angle it subtends (its radius `point_radius_m`), so that sparse points close to the viewpoint
// still occlude what lies behind them.
#pragma once

#include <vector>

#include "sketch_registration/types.h"

namespace efs::registration {

struct HprConfig {
  int num_fine_bins = 720;         ///< polar depth-buffer resolution (0.5 deg)
  double min_range_m = 0.2;        ///< ignore points closer than this (the robot itself)
  double max_range_m = 30.0;       ///< ignore points farther than this
  double point_radius_m = 0.1;     ///< half the point spacing: the angle each point occludes
  double depth_tolerance_m = 0.3;  ///< a point behind the buffer by at most this is visible
  /// Angular offset of fine bin 0's left edge [rad]; lets coarse bins be centred on k*2pi/N.
  double angle_offset_rad = 0.0;

  void validate() const;
};

/// Nearest range per fine azimuth bin around a viewpoint. Reusable without reallocation, which
/// keeps Phase-1 precomputation over ~20k candidates fast.
class PolarDepthBuffer {
 public:
  explicit PolarDepthBuffer(const HprConfig& config);

  void reset();
  /// Adds a point given relative to the viewpoint (dx, dy) [m].
  void splat(double dx_m, double dy_m);
  void splatAll(const Points2d& points_m, const Eigen::Vector2d& viewpoint_m);

  /// Fine bin of a direction (after the angle offset).
  int fineBin(double dx_m, double dy_m) const;
  /// Nearest range of a fine bin, +inf when empty.
  float depth(int fine_bin) const { return depth_[static_cast<size_t>(fine_bin)]; }
  const std::vector<float>& depths() const { return depth_; }
  const HprConfig& config() const { return config_; }

 private:
  /// Bearing of (dx, dy) plus angle_offset_rad, in [0, 2 pi): what splat and fineBin bin by.
  double bearingRad(double dx_m, double dy_m) const;
  HprConfig config_;
  double bins_per_rad_;
  std::vector<float> depth_;
};

/// The points of `points_m` visible from `viewpoint_m` (HPR). Order is preserved.
Points2d hiddenPointRemoval(const Points2d& points_m, const Eigen::Vector2d& viewpoint_m,
                            const HprConfig& config);

}  // namespace efs::registration
