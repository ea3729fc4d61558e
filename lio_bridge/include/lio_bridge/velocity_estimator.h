// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// World-frame linear velocity from positions alone: FAST-LIO2's /Odometry carries no twist.
// A polynomial in time is fitted by least squares to the positions of the last `window_s`
// seconds, far less noisy than a two-point difference. A line (fit_order 1) gives the velocity
// of the window's middle, half a window late: 0.2 m/s RMS off in a simulated cave flight at
// 100 Hz, which the controller's damping term then fights. A parabola (fit_order 2, the
// default) gives the velocity at the newest sample, exact under constant acceleration: 0.017 m/s
// RMS on the same flight; it amplifies white position noise more (0.3 m/s at 5 mm), so noisy
// odometry wants a longer window or the line.
#pragma once

#include <Eigen/Core>
#include <deque>

namespace efs::lio {

struct VelocityEstimatorConfig {
  double window_s = 0.1;  ///< fitting window [s]
  int max_samples = 50;   ///< cap on samples in the window
  int fit_order = 2;      ///< 1: line (velocity half a window late), 2: parabola (at the newest)
  void validate() const;
};

class VelocityEstimator {
 public:
  explicit VelocityEstimator(const VelocityEstimatorConfig& config = {});

  /// Adds a position; samples must come in increasing time order (older ones are ignored).
  void add(double stamp_s, const Eigen::Vector3d& p_world_m);
  /// Velocity at the newest sample (fit_order 2; the window's middle for 1, or while fewer than
  /// four samples span the window); zero until two samples exist.
  Eigen::Vector3d velocity() const;
  void reset() { samples_.clear(); }

 private:
  struct Sample {
    double t;
    Eigen::Vector3d p;
  };
  VelocityEstimatorConfig config_;
  std::deque<Sample> samples_;
};

}  // namespace efs::lio
