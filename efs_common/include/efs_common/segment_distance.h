// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#pragma once

#include <Eigen/Core>
#include <algorithm>

namespace efs {

/// Euclidean distance from p to the segment [a, b] (to a itself when a == b), in 2D or 3D.
template <int Dim>
double distanceToSegment(const Eigen::Matrix<double, Dim, 1>& p,
                         const Eigen::Matrix<double, Dim, 1>& a,
                         const Eigen::Matrix<double, Dim, 1>& b) {
  const Eigen::Matrix<double, Dim, 1> ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

}  // namespace efs
