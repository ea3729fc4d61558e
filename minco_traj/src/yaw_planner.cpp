// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/yaw_planner.h"

#include <algorithm>
#include <cmath>

#include "efs_common/angles.h"
#include "efs_common/config_check.h"

namespace efs::traj {

void YawPlannerConfig::validate() const {
  requireInRange("yaw.yaw_rate_max_radps", yaw_rate_max_radps, 0.01, 20.0);
  requireInRange("yaw.yaw_acc_max_radps2", yaw_acc_max_radps2, 0.01, 100.0);
}

YawPlanner::YawPlanner(const YawPlannerConfig& cfg) : cfg_(cfg) { cfg_.validate(); }

double YawPlanner::lookAtYaw(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                             double fallback) {
  const Eigen::Vector2d d = (to - from).head<2>();
  return d.norm() < 1e-6 ? fallback : std::atan2(d.y(), d.x());
}

YawProfile YawPlanner::plan(double y0, double r0, double target) const {
  const double V = cfg_.yaw_rate_max_radps, A = cfg_.yaw_acc_max_radps2;
  r0 = std::clamp(r0, -V, V);
  const double e = angleDiff(target, y0);  // shorter way round
  YawProfile prof(y0 + e);
  const double ds = r0 * std::abs(r0) / (2.0 * A);  // signed stopping distance
  const double s = (e - ds >= 0.0) ? 1.0 : -1.0;
  const double D = s * e, u = s * r0;
  if (std::abs(e) < 1e-12 && std::abs(r0) < 1e-12) return prof;
  double w = std::sqrt(std::max(0.0, (2.0 * A * D + u * u) / 2.0));
  w = std::min(w, V);
  // Phase 1: from u to w; phase 2: cruise at w; phase 3: brake to 0 (all in the s-direction).
  const double a1 = (w >= u) ? A : -A;
  const double t1 = std::abs(w - u) / A;
  const double d1 = (w * w - u * u) / (2.0 * a1);
  const double t3 = w / A, d3 = w * w / (2.0 * A);
  const double d2 = std::max(0.0, D - d1 - d3);
  const double t2 = w > 1e-12 ? d2 / w : 0.0;
  double y = y0;
  if (t1 > 0.0) {
    prof.addSegment({t1, y, s * u, s * a1});
    y += s * d1;
  }
  if (t2 > 0.0) {
    prof.addSegment({t2, y, s * w, 0.0});
    y += s * d2;
  }
  if (t3 > 0.0) prof.addSegment({t3, y, s * w, -s * A});
  return prof;
}

}  // namespace efs::traj
