// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "lio_bridge/velocity_estimator.h"

#include <Eigen/Cholesky>

#include "efs_common/config_check.h"

namespace efs::lio {

void VelocityEstimatorConfig::validate() const {
  requireInRange("window_s", window_s, 1e-3, 10.0);
  requireInRange("max_samples", max_samples, 2, 10000);
  requireInRange("fit_order", fit_order, 1, 2);
}

VelocityEstimator::VelocityEstimator(const VelocityEstimatorConfig& config) : config_(config) {
  config_.validate();
}

void VelocityEstimator::add(double stamp_s, const Eigen::Vector3d& p_world_m) {
  if (!samples_.empty() && stamp_s <= samples_.back().t) return;
  samples_.push_back({stamp_s, p_world_m});
  while (samples_.size() > static_cast<size_t>(config_.max_samples) ||
         (samples_.size() > 2 && stamp_s - samples_.front().t > config_.window_s)) {
    samples_.pop_front();
  }
}

Eigen::Vector3d VelocityEstimator::velocity() const {
  if (samples_.size() < 2) return Eigen::Vector3d::Zero();
  if (config_.fit_order == 2 && samples_.size() >= 4) {
    // p(t) = c0 + c1 t + c2 t^2 with t relative to the newest sample: c1 is its velocity. Time
    // is scaled to the window span for conditioning.
    const double t_new = samples_.back().t;
    const double span = t_new - samples_.front().t;
    if (span > 0.0) {
      Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
      Eigen::Matrix3d rhs = Eigen::Matrix3d::Zero();  // column per axis
      for (const auto& s : samples_) {
        const double u = (s.t - t_new) / span;
        const Eigen::Vector3d f(1.0, u, u * u);
        N += f * f.transpose();
        rhs += f * s.p.transpose();
      }
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(N);
      if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
        const Eigen::Matrix3d c = ldlt.solve(rhs);
        if (c.allFinite()) return c.row(1).transpose() / span;
      }
    }
  }
  // Least-squares slope of p(t), per axis, with t centred for conditioning.
  double t_mean = 0.0;
  Eigen::Vector3d p_mean = Eigen::Vector3d::Zero();
  for (const auto& s : samples_) {
    t_mean += s.t;
    p_mean += s.p;
  }
  t_mean /= samples_.size();
  p_mean /= static_cast<double>(samples_.size());
  double stt = 0.0;
  Eigen::Vector3d stp = Eigen::Vector3d::Zero();
  for (const auto& s : samples_) {
    const double dt = s.t - t_mean;
    stt += dt * dt;
    stp += dt * (s.p - p_mean);
  }
  return stt > 0.0 ? Eigen::Vector3d(stp / stt) : Eigen::Vector3d::Zero();
}

}  // namespace efs::lio
