// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// World-frame linear velocity from positions alone: FAST-LIO2's /Odometry carries no twist. A
// line is fitted by least squares to the positions of the last `window_s` seconds, which is
// far less noisy than a two-point difference and has a known lag of half the window.
#pragma once

#include <Eigen/Core>
#include <deque>

namespace efs::lio {

struct VelocityEstimatorConfig {
  double window_s = 0.1;  ///< fitting window [s]
  int max_samples = 50;   ///< cap on samples in the window
  void validate() const;
};

class VelocityEstimator {
 public:
  explicit VelocityEstimator(const VelocityEstimatorConfig& config = {});

  /// Adds a position; samples must come in increasing time order (older ones are ignored).
  void add(double stamp_s, const Eigen::Vector3d& p_world_m);
  /// Velocity at the newest sample; zero until two samples exist.
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
