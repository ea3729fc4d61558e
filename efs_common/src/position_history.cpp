// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/position_history.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "efs_common/config_check.h"

namespace efs {

void PositionHistoryConfig::validate(const std::string& key_prefix) const {
  requireInRange(key_prefix + "keep_s", keep_s, 0.1, 60.0);
  requireInRange(key_prefix + "max_gap_s", max_gap_s, 1e-3, 10.0);
  requireInRange(key_prefix + "max_extrapolation_s", max_extrapolation_s, 0.0, 1.0);
}

PositionHistory::PositionHistory(const PositionHistoryConfig& config) : config_(config) {
  config_.validate();
}

bool PositionHistory::add(double stamp_s, const Eigen::Vector3d& p_world_m) {
  if (!std::isfinite(stamp_s) || !p_world_m.allFinite()) return false;
  if (!samples_.empty() && stamp_s < samples_.back().stamp_s - config_.keep_s) samples_.clear();
  auto it = samples_.end();
  while (it != samples_.begin() && std::prev(it)->stamp_s > stamp_s) --it;
  if (it != samples_.begin() && std::prev(it)->stamp_s == stamp_s) {
    std::prev(it)->p_world_m = p_world_m;  // a repeated stamp: the newer message wins
  } else {
    samples_.insert(it, {stamp_s, p_world_m});
  }
  const double oldest_kept = samples_.back().stamp_s - config_.keep_s;
  while (samples_.size() > 1 && samples_.front().stamp_s < oldest_kept) samples_.pop_front();
  return true;
}

std::optional<Eigen::Vector3d> PositionHistory::at(double stamp_s, std::string* why) const {
  auto fail = [&](const std::string& reason) -> std::optional<Eigen::Vector3d> {
    if (why) *why = reason;
    return std::nullopt;
  };
  if (!std::isfinite(stamp_s)) return fail("stamp is not finite");
  if (samples_.empty()) return fail("no odometry yet");
  std::ostringstream os;
  const Sample& newest = samples_.back();
  if (stamp_s >= newest.stamp_s) {
    if (stamp_s - newest.stamp_s <= config_.max_extrapolation_s) return newest.p_world_m;
    os << "stamp " << stamp_s << " s is " << stamp_s - newest.stamp_s
       << " s past the newest odometry (max_extrapolation_s " << config_.max_extrapolation_s << ")";
    return fail(os.str());
  }
  if (stamp_s < samples_.front().stamp_s) {
    os << "stamp " << stamp_s << " s is older than the odometry kept (from "
       << samples_.front().stamp_s << " s)";
    return fail(os.str());
  }
  const auto after = std::upper_bound(samples_.begin(), samples_.end(), stamp_s,
                                      [](double t, const Sample& s) { return t < s.stamp_s; });
  const Sample& b = *after;
  const Sample& a = *std::prev(after);
  const double gap = b.stamp_s - a.stamp_s;
  if (gap > config_.max_gap_s) {
    os << "stamp " << stamp_s << " s falls in an odometry gap of " << gap << " s (max_gap_s "
       << config_.max_gap_s << ")";
    return fail(os.str());
  }
  const double w = gap > 0.0 ? (stamp_s - a.stamp_s) / gap : 0.0;
  return ((1.0 - w) * a.p_world_m + w * b.p_world_m).eval();
}

std::optional<Eigen::Vector3d> PositionHistory::velocity(double window_s) const {
  if (samples_.empty() || !(window_s > 0.0) || !std::isfinite(window_s)) return std::nullopt;
  const Sample& newest = samples_.back();
  const std::optional<Eigen::Vector3d> before = at(newest.stamp_s - window_s);
  if (!before) return std::nullopt;
  return (newest.p_world_m - *before) / window_s;
}

}  // namespace efs
