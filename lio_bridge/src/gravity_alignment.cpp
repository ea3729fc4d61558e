// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "lio_bridge/gravity_alignment.h"

#include "efs_common/config_check.h"

namespace efs::lio {

void GravityAlignmentConfig::validate() const {
  requireInRange("samples_needed", samples_needed, 1, 100000);
  requireInRange("max_accel_spread_mps2", max_accel_spread_mps2, 1e-3, 100.0);
}

GravityAligner::GravityAligner(const GravityAlignmentConfig& config) : config_(config) {
  config_.validate();
}

void GravityAligner::add(const Eigen::Vector3d& accel) {
  if (!accel.allFinite() || static_cast<int>(samples_.size()) >= config_.samples_needed) return;
  samples_.push_back(accel);
  sum_ += accel;
  if (static_cast<int>(samples_.size()) == config_.samples_needed) {
    const Eigen::Vector3d mean = sum_ / static_cast<double>(samples_.size());
    for (const auto& a : samples_)
      moved_ = moved_ || (a - mean).norm() > config_.max_accel_spread_mps2;
  }
}

std::optional<Eigen::Quaterniond> GravityAligner::rotation() const {
  if (static_cast<int>(samples_.size()) < config_.samples_needed || moved_) return std::nullopt;
  const Eigen::Vector3d mean = sum_ / static_cast<double>(samples_.size());
  if (mean.norm() < 1.0) return std::nullopt;  // free fall or a dead sensor: no gravity to align
  return alignToZ(mean.normalized());
}

void GravityAligner::reset() {
  samples_.clear();
  sum_.setZero();
  moved_ = false;
}

Eigen::Quaterniond GravityAligner::alignToZ(const Eigen::Vector3d& up_measured) {
  return Eigen::Quaterniond::FromTwoVectors(up_measured.normalized(), Eigen::Vector3d::UnitZ());
}

}  // namespace efs::lio
