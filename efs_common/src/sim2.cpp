// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/sim2.h"

#include <algorithm>
#include <sstream>

namespace efs {

Sim2 Sim2::fromLinear(const Eigen::Matrix2d& l, const Eigen::Vector2d& t) {
  Sim2 out;
  out.t_m = t;
  out.reflected = l.determinant() < 0.0;
  // m = s R S' with S' = F S F: proper, so its polar decomposition gives R.
  Eigen::Matrix2d m = l;
  if (out.reflected) m.col(1) = -m.col(1);
  const double tolerance = 1e-12 * std::max(m.cwiseAbs().maxCoeff(), 1e-300);
  if (std::abs(m(0, 0) - m(1, 1)) <= tolerance && std::abs(m(0, 1) + m(1, 0)) <= tolerance) {
    // A scaled rotation: read it off directly (exactly as a similarity always was).
    out.scale = std::sqrt(std::abs(l.determinant()));
    const Eigen::Matrix2d r = m / out.scale;
    out.yaw_rad = std::atan2(r(1, 0), r(0, 0));
    return out;
  }
  out.yaw_rad = std::atan2(m(1, 0) - m(0, 1), m(0, 0) + m(1, 1));
  const double c = std::cos(out.yaw_rad), sn = std::sin(out.yaw_rad);
  Eigen::Matrix2d r;
  r << c, -sn, sn, c;
  Eigen::Matrix2d p = r.transpose() * m;  // symmetric positive definite: s S'
  out.scale = std::sqrt(std::abs(p.determinant()));
  p /= out.scale;
  if (out.reflected) {
    p(0, 1) = -p(0, 1);
    p(1, 0) = -p(1, 0);
  }
  const double a = p(0, 0), d = p(1, 1), b = 0.5 * (p(0, 1) + p(1, 0));
  out.stretch = 0.5 * (a + d) + std::hypot(0.5 * (a - d), b);
  out.stretch_axis_rad = 0.5 * std::atan2(2.0 * b, a - d);
  if (!(out.stretch > 1.0 + 1e-12)) {
    out.stretch = 1.0;
    out.stretch_axis_rad = 0.0;
  }
  return out;
}

std::string Sim2::toString() const {
  std::ostringstream os;
  os << "Sim2{yaw_rad=" << yaw_rad << ", scale=" << scale << ", t_m=(" << t_m.x() << ", " << t_m.y()
     << ")" << (reflected ? ", reflected" : "");
  if (!isSimilarity()) os << ", stretch=" << stretch << " along " << stretch_axis_rad << " rad";
  os << "}";
  return os.str();
}

}  // namespace efs
