// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "lio_bridge/input_monitor.h"

#include <cmath>
#include <sstream>

#include "efs_common/config_check.h"

namespace efs::lio {

void InputMonitorConfig::validate() const {
  requireInRange("stale_timeout_s", stale_timeout_s, 1e-3, 60.0);
  requireInRange("max_speed_mps", max_speed_mps, 0.1, 1000.0);
  requireInRange("min_jump_m", min_jump_m, 0.0, 1000.0);
}

const char* toString(InputHealth health) {
  switch (health) {
    case InputHealth::kNoData:
      return "no data";
    case InputHealth::kHealthy:
      return "healthy";
    case InputHealth::kStale:
      return "stale";
  }
  return "unknown";
}

InputMonitor::InputMonitor(const InputMonitorConfig& config) : config_(config) {
  config_.validate();
}

InputMonitor::Result InputMonitor::check(const OdometrySample& s) {
  std::ostringstream why;
  const Eigen::Vector4d q = s.q_world_body.coeffs();
  if (!std::isfinite(s.stamp_s) || !s.p_world_m.allFinite() || !q.allFinite()) {
    why << "odometry rejected: non-finite stamp, position or orientation";
  } else if (std::abs(q.norm() - 1.0) > 1e-2) {
    why << "odometry rejected: orientation quaternion has norm " << q.norm() << ", not 1";
  } else if (last_ && s.stamp_s <= last_->stamp_s) {
    why << "odometry rejected: stamp " << s.stamp_s << " s is not after the previous "
        << last_->stamp_s << " s (time went backwards or repeated)";
  }
  if (!why.str().empty()) {
    ++rejected_;
    return {Verdict::kRejected, why.str()};
  }
  if (last_) {
    const double dist = (s.p_world_m - last_->p_world_m).norm();
    const double dt = s.stamp_s - last_->stamp_s;
    if (dist > config_.min_jump_m && dist / dt > config_.max_speed_mps) {
      why << "odometry jumped " << dist << " m in " << dt << " s (" << dist / dt
          << " m/s > max_speed_mps " << config_.max_speed_mps << "); following the new pose";
      ++jumps_;
      last_ = s;
      return {Verdict::kJump, why.str()};
    }
  }
  last_ = s;
  return {};
}

InputHealth InputMonitor::health(double now_s) const {
  if (!last_) return InputHealth::kNoData;
  return now_s - last_->stamp_s > config_.stale_timeout_s ? InputHealth::kStale
                                                          : InputHealth::kHealthy;
}

}  // namespace efs::lio
