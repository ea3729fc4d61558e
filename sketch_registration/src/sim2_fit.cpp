// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/sim2_fit.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "efs_common/angles.h"

namespace efs::registration {

Sim2Fit fitSim2(const Points2d& c_sketch, const Points2d& p_world, bool reflected, double scale_min,
                double scale_max, const std::vector<double>* weights) {
  Sim2Fit out;
  const size_t n = std::min(c_sketch.size(), p_world.size());
  if (n < 2) return out;
  double wsum = 0.0;
  Eigen::Vector2d cm = Eigen::Vector2d::Zero(), pm = Eigen::Vector2d::Zero();
  auto src = [&](size_t i) {
    return reflected ? Eigen::Vector2d(c_sketch[i].x(), -c_sketch[i].y()) : c_sketch[i];
  };
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? (*weights)[i] : 1.0;
    wsum += w;
    cm += w * src(i);
    pm += w * p_world[i];
  }
  if (!(wsum > 0.0)) return out;
  cm /= wsum;
  pm /= wsum;
  double a = 0.0, b = 0.0, var_c = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? (*weights)[i] : 1.0;
    const Eigen::Vector2d c = src(i) - cm, p = p_world[i] - pm;
    a += w * (c.x() * p.x() + c.y() * p.y());
    b += w * (c.x() * p.y() - c.y() * p.x());
    var_c += w * c.squaredNorm();
  }
  if (!(var_c > 1e-12)) return out;
  // In 2D the optimal rotation is the angle of the complex cross-covariance sum(conj(c) p).
  const double yaw = std::atan2(b, a);
  double s = std::hypot(a, b) / var_c;
  s = std::min(scale_max, std::max(scale_min, s));
  const Eigen::Rotation2Dd rot(yaw);
  const Eigen::Vector2d t = pm - s * (rot * cm);
  out.T_world_sketch = Sim2(yaw, s, t, reflected);
  double ss = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? (*weights)[i] : 1.0;
    ss += w * (out.T_world_sketch.apply(c_sketch[i]) - p_world[i]).squaredNorm();
  }
  out.rms_residual_m = std::sqrt(ss / wsum);
  out.ok = out.T_world_sketch.isFinite() && s > 0.0;
  return out;
}

namespace {
/// The stretch matrix of `decomposed`, its ratio capped at stretch_max.
Eigen::Matrix2d cappedStretch(const Sim2& decomposed, double stretch_max) {
  Sim2 only_stretch;
  only_stretch.stretch = std::min(decomposed.stretch, stretch_max);
  only_stretch.stretch_axis_rad = decomposed.stretch_axis_rad;
  return only_stretch.stretchMatrix();
}

/// The stretch (determinant 1) of a symmetric positive definite `m` (its decomposition has yaw 0),
/// capped; false if `m` is not positive definite.
bool boundedStretch(const Eigen::Matrix2d& m, double stretch_max, Eigen::Matrix2d* stretch) {
  if (!(m.determinant() > 0.0 && m.trace() > 0.0)) return false;
  *stretch = cappedStretch(Sim2::fromLinear(m, Eigen::Vector2d::Zero()), stretch_max);
  return true;
}
}  // namespace

Sim2Fit fitStretchedSim2(const Points2d& c_sketch, const Points2d& p_world, bool reflected,
                         double scale_min, double scale_max, double stretch_max,
                         const std::vector<double>* weights, const Sim2* start) {
  const size_t n = std::min(c_sketch.size(), p_world.size());
  if (!(stretch_max > 1.0) && (!start || start->isSimilarity())) {
    return fitSim2(c_sketch, p_world, reflected, scale_min, scale_max, weights);
  }
  if (n < 2) return {};
  Eigen::Matrix2d S = start ? start->stretchMatrix() : Eigen::Matrix2d::Identity();
  double wsum = 0.0;
  Eigen::Vector2d cm = Eigen::Vector2d::Zero(), pm = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? (*weights)[i] : 1.0;
    wsum += w;
    cm += w * c_sketch[i];
    pm += w * p_world[i];
  }
  if (!(wsum > 0.0)) return {};
  cm /= wsum;
  pm /= wsum;
  // The stretch is observable only where the points spread along both axes.
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero(), cross = Eigen::Matrix2d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? (*weights)[i] : 1.0;
    const Eigen::Vector2d c = c_sketch[i] - cm;
    cov += w * c * c.transpose();
    cross += w * (p_world[i] - pm) * c.transpose();
  }
  const double spread_lo = 0.5 * cov.trace() - std::hypot(0.5 * (cov(0, 0) - cov(1, 1)), cov(0, 1));
  const bool refined = stretch_max > 1.0 && spread_lo > 0.01 * cov.trace();
  if (refined) {
    // Start from the stretch of the unconstrained affine fit (capped): alternating from no
    // stretch converges slowly where the points spread far more along one axis (a hall, a
    // tunnel).
    const Sim2 affine = Sim2::fromLinear(cross * cov.inverse(), Eigen::Vector2d::Zero());
    if (affine.isFinite() && affine.reflected == reflected) S = cappedStretch(affine, stretch_max);
  }
  const Eigen::Matrix2d F =
      reflected ? Eigen::Vector2d(1, -1).asDiagonal().toDenseMatrix() : Eigen::Matrix2d::Identity();
  Sim2Fit fit;
  Points2d c(n);
  constexpr int kRounds = 6;
  for (int round = 0; round < kRounds; ++round) {
    for (size_t i = 0; i < n; ++i) c[i] = S * c_sketch[i];
    fit = fitSim2(c, p_world, reflected, scale_min, scale_max, weights);
    if (!fit.ok || !refined || round + 1 == kRounds) break;
    // Given R: p - pm = s R F S (c - cm), so F R^T (p - pm) = M (c - cm) with M = s S symmetric.
    const Eigen::Matrix2d Rt =
        Eigen::Rotation2Dd(fit.T_world_sketch.yaw_rad).toRotationMatrix().transpose();
    Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
    Eigen::Vector3d atb = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < n; ++i) {
      const double w = weights ? (*weights)[i] : 1.0;
      const Eigen::Vector2d u = c_sketch[i] - cm, v = F * (Rt * (p_world[i] - pm));
      const Eigen::Vector3d rx(u.x(), u.y(), 0.0), ry(0.0, u.x(), u.y());
      ata += w * (rx * rx.transpose() + ry * ry.transpose());
      atb += w * (rx * v.x() + ry * v.y());
    }
    const Eigen::Vector3d m = ata.ldlt().solve(atb);
    Eigen::Matrix2d M;
    M << m(0), m(1), m(1), m(2);
    if (!m.allFinite() || !boundedStretch(M, stretch_max, &S)) break;
  }
  if (!fit.ok) return fit;
  // fitSim2 saw S c: the transform of c is s R F S.
  const Sim2 T = Sim2::fromLinear(fit.T_world_sketch.linear() * S, fit.T_world_sketch.t_m);
  fit.T_world_sketch = T;
  double ss = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double w = weights ? (*weights)[i] : 1.0;
    ss += w * (T.apply(c_sketch[i]) - p_world[i]).squaredNorm();
  }
  fit.rms_residual_m = std::sqrt(ss / wsum);
  fit.ok = T.isFinite() && T.scale > 0.0;
  return fit;
}

Sim2Fit fitSim2Either(const Points2d& c_sketch, const Points2d& p_world, bool prefer_reflected,
                      double ambiguity_ratio) {
  const Sim2Fit proper = fitSim2(c_sketch, p_world, false);
  const Sim2Fit mirror = fitSim2(c_sketch, p_world, true);
  if (!proper.ok) return mirror;
  if (!mirror.ok) return proper;
  const double lo = std::min(proper.rms_residual_m, mirror.rms_residual_m);
  const double hi = std::max(proper.rms_residual_m, mirror.rms_residual_m);
  // Residuals relative to the spread: collinear point sets fit both handednesses equally.
  double spread = 0.0;
  Eigen::Vector2d pm = Eigen::Vector2d::Zero();
  for (const auto& p : p_world) pm += p;
  pm /= static_cast<double>(p_world.size());
  for (const auto& p : p_world) spread += (p - pm).squaredNorm();
  spread = std::sqrt(spread / static_cast<double>(p_world.size()));
  if (hi - lo <= ambiguity_ratio * std::max(spread, 1e-9)) {
    return prefer_reflected ? mirror : proper;
  }
  return proper.rms_residual_m <= mirror.rms_residual_m ? proper : mirror;
}

double transformDistance(const Sim2& a, const Sim2& b, const TransformDistanceWeights& w) {
  if (a.reflected != b.reflected) return std::numeric_limits<double>::infinity();
  return w.lambda_t * (a.t_m - b.t_m).norm() +
         w.lambda_r * std::abs(angleDiff(a.yaw_rad, b.yaw_rad)) +
         w.lambda_s * std::abs(a.scale - b.scale);
}

double transformDistanceLowerBound(const Sim2& a, const Sim2& b,
                                   const TransformDistanceWeights& w) {
  if (!(w.lambda_t > 0.0 && w.lambda_r >= 0.0 && w.lambda_s >= 0.0)) return 0.0;
  return w.lambda_t * (a.t_m - b.t_m).cwiseAbs().maxCoeff();
}

std::vector<double> fourierDescriptor(const Points2d& polygon, int max_components) {
  const int n = static_cast<int>(polygon.size());
  std::vector<double> out;
  if (n < 3) return out;
  std::vector<std::complex<double>> z(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    double re = 0.0, im = 0.0;
    for (int i = 0; i < n; ++i) {
      const double a = -2.0 * M_PI * k * i / n;
      const double c = std::cos(a), s = std::sin(a);
      re += polygon[i].x() * c - polygon[i].y() * s;
      im += polygon[i].x() * s + polygon[i].y() * c;
    }
    z[static_cast<size_t>(k)] = {re, im};
  }
  // Normalise by the largest non-DC magnitude: |Z_1| alone vanishes for some shapes.
  double norm = 0.0;
  for (int k = 1; k < n; ++k) norm = std::max(norm, std::abs(z[static_cast<size_t>(k)]));
  if (!(norm > 1e-12)) return std::vector<double>(static_cast<size_t>(n - 1), 0.0);
  for (int k = 1; k < n && static_cast<int>(out.size()) < max_components; ++k) {
    out.push_back(std::abs(z[static_cast<size_t>(k)]) / norm);
  }
  return out;
}

double fourierDistance(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n = std::max(a.size(), b.size());
  double s = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double x = i < a.size() ? a[i] : 0.0, y = i < b.size() ? b[i] : 0.0;
    s += (x - y) * (x - y);
  }
  return std::sqrt(s);
}

}  // namespace efs::registration
