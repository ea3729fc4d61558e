// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// atan and atan2 to within 5e-8 rad, several times cheaper than the C library's correctly
// rounded ones. Polar depth buffers bin every sketch and map point by its bearing (a fine bin is
// about 1e-3 rad wide): std::atan2 and std::atan took a third of registration_bench's run, most
// of it in Phase 1, which bins the sketch's walls around each of ~25 000 candidate locations.
#pragma once

#include <cmath>

namespace efs {

namespace detail {
/// atan(t) for t in [0, 1]: t times a polynomial in t^2, least-squares fitted on Chebyshev nodes
/// (largest error 4.1e-8 rad over [0, 1]).
inline double atanUnit(double t) {
  const double s = t * t;
  double p = -0.004073290392714761;
  p = p * s + 0.021946535890084336;
  p = p * s - 0.056063057499983644;
  p = p * s + 0.09656246758309978;
  p = p * s - 0.1391579798386541;
  p = p * s + 0.19948508009066915;
  p = p * s - 0.33330106578587604;
  p = p * s + 0.9999994368144962;
  return t * p;
}
}  // namespace detail

/// atan(x); non-finite input falls back to std::atan.
inline double fastAtan(double x) {
  const double a = std::abs(x);
  if (!std::isfinite(a)) return std::atan(x);
  const double r = a <= 1.0 ? detail::atanUnit(a) : 0.5 * M_PI - detail::atanUnit(1.0 / a);
  return std::copysign(r, x);
}

/// atan2(y, x) in [-pi, pi]; (0, 0) gives 0 and non-finite input falls back to std::atan2.
inline double fastAtan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  if (!std::isfinite(ax) || !std::isfinite(ay)) return std::atan2(y, x);
  if (ax == 0.0 && ay == 0.0) return std::atan2(y, x);
  double r = ay <= ax ? detail::atanUnit(ay / ax) : 0.5 * M_PI - detail::atanUnit(ax / ay);
  if (x < 0.0) r = M_PI - r;
  return std::copysign(r, y);
}

}  // namespace efs
