// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "se3_controller/reference_shapes.h"

#include <cmath>

namespace efs::control {

double FigureEight::angularRate() const { return peak_speed_mps / (amplitude_m * std::sqrt(2.0)); }

double FigureEight::period() const { return 2.0 * M_PI / angularRate(); }

FlatReference FigureEight::at(double t) const {
  const double A = amplitude_m, w = angularRate();
  const double s = std::sin(w * t), c = std::cos(w * t), s2 = std::sin(2 * w * t),
               c2 = std::cos(2 * w * t);
  FlatReference r;
  r.stamp_s = t;
  r.p_world_m = Eigen::Vector3d(center_m.x() + A * s, center_m.y() + 0.5 * A * s2, height_m);
  r.v_world_mps = Eigen::Vector3d(A * w * c, A * w * c2, 0);
  r.a_world_mps2 = Eigen::Vector3d(-A * w * w * s, -2 * A * w * w * s2, 0);
  r.j_world_mps3 = Eigen::Vector3d(-A * w * w * w * c, -4 * A * w * w * w * c2, 0);
  r.yaw_rad = std::atan2(r.v_world_mps.y(), r.v_world_mps.x());
  const Eigen::Vector2d v2 = r.v_world_mps.head<2>(), a2 = r.a_world_mps2.head<2>();
  r.yaw_rate_radps = (v2.x() * a2.y() - v2.y() * a2.x()) / v2.squaredNorm();
  return r;
}

FlatReference hoverReference(const Eigen::Vector3d& p_world_m, double yaw_rad, double t_s) {
  FlatReference r;
  r.stamp_s = t_s;
  r.p_world_m = p_world_m;
  r.yaw_rad = yaw_rad;
  return r;
}

}  // namespace efs::control
