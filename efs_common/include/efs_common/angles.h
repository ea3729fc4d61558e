// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#pragma once

#include <cmath>

namespace efs {

/// Wraps an angle to (-pi, pi].
inline double wrapAngle(double a_rad) {
  a_rad = std::remainder(a_rad, 2.0 * M_PI);
  return a_rad <= -M_PI ? a_rad + 2.0 * M_PI : a_rad;
}

/// Signed smallest difference a - b, in (-pi, pi].
inline double angleDiff(double a_rad, double b_rad) { return wrapAngle(a_rad - b_rad); }

inline constexpr double deg2rad(double d) { return d * M_PI / 180.0; }
inline constexpr double rad2deg(double r) { return r * 180.0 / M_PI; }

}  // namespace efs
