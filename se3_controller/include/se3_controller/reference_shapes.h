// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Analytic flat references for closed-loop tests and benchmarks: hover and the figure-eight
// (lemniscate of Gerono x = A sin(wt), y = (A/2) sin(2wt)) flown with the heading along the
// velocity, the tracking target.
#pragma once

#include <Eigen/Core>

#include "se3_controller/se3_controller.h"

namespace efs::control {

struct FigureEight {
  double amplitude_m = 5.0;     ///< A: half the extent along x
  double peak_speed_mps = 3.0;  ///< reached at the crossing, A w sqrt(2)
  double height_m = 1.5;
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();
  double angularRate() const;  ///< w [rad/s]
  double period() const;       ///< 2 pi / w [s]
  /// p, v, a, jerk, yaw along the velocity and its rate at t.
  FlatReference at(double t_s) const;
};

FlatReference hoverReference(const Eigen::Vector3d& p_world_m, double yaw_rad, double t_s);

}  // namespace efs::control
