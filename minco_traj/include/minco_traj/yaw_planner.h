// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Yaw trajectory that turns the sensor toward a look-at direction (the unexplored region the
// planner is heading for) as fast as the limits allow: the time-optimal rest-to-rest profile of
// a double integrator with |yaw rate| <= yaw_rate_max and |yaw acceleration| <= yaw_acc_max,
// from the current (yaw, yaw rate) to (target, 0) along the shorter way round. Limits hold
// exactly by construction (bang-coast-bang segments).
#pragma once

#include <Eigen/Core>

#include "minco_traj/trajectory.h"

namespace efs::traj {

struct YawPlannerConfig {
  double yaw_rate_max_radps = 4.0;
  double yaw_acc_max_radps2 = 4.0;
  void validate() const;
};

class YawPlanner {
 public:
  explicit YawPlanner(const YawPlannerConfig& cfg = {});
  YawProfile plan(double yaw0_rad, double yaw_rate0_radps, double target_yaw_rad) const;
  /// Yaw of the horizontal direction from `from` to `to` (keeps `fallback` if they coincide).
  static double lookAtYaw(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double fallback);

 private:
  YawPlannerConfig cfg_;
};

}  // namespace efs::traj
