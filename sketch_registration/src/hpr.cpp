// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/hpr.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "efs_common/config_check.h"
#include "efs_common/fast_atan.h"

namespace efs::registration {

void HprConfig::validate() const {
  requireInRange("num_fine_bins", num_fine_bins, 8, 1 << 16);
  requireInRange("min_range_m", min_range_m, 0.0, 1e6);
  requirePositive("max_range_m", max_range_m);
  requireThat(max_range_m > min_range_m, "max_range_m", "must be > min_range_m");
  requireInRange("point_radius_m", point_radius_m, 0.0, 100.0);
  requireInRange("depth_tolerance_m", depth_tolerance_m, 0.0, 100.0);
  requireInRange("angle_offset_rad", angle_offset_rad, -2.0 * M_PI, 2.0 * M_PI);
}

PolarDepthBuffer::PolarDepthBuffer(const HprConfig& config)
    : config_(config), bins_per_rad_(config.num_fine_bins / (2.0 * M_PI)) {
  config_.validate();
  depth_.assign(static_cast<size_t>(config_.num_fine_bins), std::numeric_limits<float>::infinity());
}

void PolarDepthBuffer::reset() {
  std::fill(depth_.begin(), depth_.end(), std::numeric_limits<float>::infinity());
}

double PolarDepthBuffer::bearingRad(double dx_m, double dy_m) const {
  double a = fastAtan2(dy_m, dx_m) + config_.angle_offset_rad;
  if (a < 0.0) a += 2.0 * M_PI;
  if (a >= 2.0 * M_PI) a -= 2.0 * M_PI;
  return a;
}

int PolarDepthBuffer::fineBin(double dx_m, double dy_m) const {
  const double a = bearingRad(dx_m, dy_m);
  const int n = config_.num_fine_bins;
  return std::min(n - 1, std::max(0, static_cast<int>(a * bins_per_rad_)));
}

void PolarDepthBuffer::splat(double dx_m, double dy_m) {
  const double r2 = dx_m * dx_m + dy_m * dy_m;
  if (!(r2 >= config_.min_range_m * config_.min_range_m) ||
      r2 > config_.max_range_m * config_.max_range_m) {
    return;
  }
  const double r = std::sqrt(r2);
  const double center = bearingRad(dx_m, dy_m) * bins_per_rad_;
  const int n = config_.num_fine_bins;
  // Half the subtended angle, in bins; capped so a point on the viewpoint cannot blank half the
  // horizon.
  const double half = std::min(fastAtan(config_.point_radius_m / r) * bins_per_rad_, n / 8.0);
  const int lo = static_cast<int>(std::floor(center - half));
  const int hi = static_cast<int>(std::floor(center + half));
  const float rf = static_cast<float>(r);
  for (int k = lo; k <= hi; ++k) {
    const int idx = k < 0 ? k + n : (k >= n ? k - n : k);
    float& d = depth_[static_cast<size_t>(idx)];
    if (rf < d) d = rf;
  }
}

void PolarDepthBuffer::splatAll(const Points2d& points_m, const Eigen::Vector2d& viewpoint_m) {
  for (const auto& p : points_m) splat(p.x() - viewpoint_m.x(), p.y() - viewpoint_m.y());
}

Points2d hiddenPointRemoval(const Points2d& points_m, const Eigen::Vector2d& viewpoint_m,
                            const HprConfig& config) {
  PolarDepthBuffer buffer(config);
  buffer.splatAll(points_m, viewpoint_m);
  Points2d visible;
  const double rmin2 = config.min_range_m * config.min_range_m;
  const double rmax2 = config.max_range_m * config.max_range_m;
  for (const auto& p : points_m) {
    const Eigen::Vector2d d = p - viewpoint_m;
    const double r2 = d.squaredNorm();
    if (!(r2 >= rmin2) || r2 > rmax2) continue;
    const double r = std::sqrt(r2);
    if (r <= buffer.depth(buffer.fineBin(d.x(), d.y())) + config.depth_tolerance_m) {
      visible.push_back(p);
    }
  }
  return visible;
}

}  // namespace efs::registration
