// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The 2D transform that maps the sketch's metric frame into the world (LIO) frame:
//   p_world_xy = scale * R(yaw) * F * S * p_sketch + t,
// a similarity (the paper's model, S = I) or, with a stretch S, any 2D affine map. F = diag(1, -1)
// for a mirror-image drawing, else I. S is symmetric with determinant 1: a hand drawing's aspect
// error (a hall drawn 8 % too long and 8 % too narrow), which no similarity absorbs over a large
// drawing. Registration bounds it; this type does not.
// TF cannot carry scale, which is why this type (not a tf2 transform) travels between modules.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <string>

namespace efs {

/// Rotation by `yaw_rad`, uniform `scale`, then translation `t_m`; before them, optionally a
/// reflection about the source x axis (`reflected`, a mirror-image sketch) and a stretch.
struct Sim2 {
  double yaw_rad = 0.0;
  double scale = 1.0;
  Eigen::Vector2d t_m = Eigen::Vector2d::Zero();
  bool reflected = false;
  /// The source is stretched by `stretch` (>= 1) along the source-frame direction
  /// `stretch_axis_rad` and shrunk by 1 / stretch across it (area kept). 1: a similarity.
  double stretch = 1.0;
  double stretch_axis_rad = 0.0;

  Sim2() = default;
  Sim2(double yaw, double s, const Eigen::Vector2d& t, bool reflect = false)
      : yaw_rad(yaw), scale(s), t_m(t), reflected(reflect) {}

  static Sim2 identity() { return Sim2(); }

  bool isSimilarity() const { return stretch == 1.0; }

  /// S: symmetric, determinant 1, eigenvalues stretch and 1 / stretch.
  Eigen::Matrix2d stretchMatrix() const {
    const double c = std::cos(stretch_axis_rad), sn = std::sin(stretch_axis_rad);
    Eigen::Matrix2d q;
    q << c, -sn, sn, c;
    return q * Eigen::Vector2d(stretch, 1.0 / stretch).asDiagonal() * q.transpose();
  }

  /// The linear part s * R * F * S.
  Eigen::Matrix2d linear() const {
    const double c = std::cos(yaw_rad), sn = std::sin(yaw_rad);
    Eigen::Matrix2d a;
    a << c, -sn, sn, c;
    if (reflected) a.col(1) = -a.col(1);
    if (!isSimilarity()) a = a * stretchMatrix();
    return scale * a;
  }

  Eigen::Vector2d apply(const Eigen::Vector2d& p) const { return linear() * p + t_m; }
  Eigen::Vector2d operator*(const Eigen::Vector2d& p) const { return apply(p); }

  /// Applies to the horizontal part of a 3D point; the vertical axis is decoupled (paper Sec. V).
  Eigen::Vector3d applyXY(const Eigen::Vector3d& p) const {
    const Eigen::Vector2d q = apply(p.head<2>());
    return {q.x(), q.y(), p.z()};
  }

  /// Composition: (a * b)(p) = a(b(p)).
  Sim2 operator*(const Sim2& b) const {
    const Eigen::Matrix2d l = linear() * b.linear();
    return fromLinear(l, apply(b.t_m));
  }

  Sim2 inverse() const {
    const Eigen::Matrix2d inv = linear().inverse();
    return fromLinear(inv, -inv * t_m);
  }

  /// 3x3 homogeneous matrix.
  Eigen::Matrix3d matrix() const {
    Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
    m.topLeftCorner<2, 2>() = linear();
    m.topRightCorner<2, 1>() = t_m;
    return m;
  }

  /// Decomposes an invertible linear map into s * R * F * S (polar decomposition; unique). A map
  /// that is a scaled rotation within rounding comes back with stretch exactly 1.
  static Sim2 fromLinear(const Eigen::Matrix2d& l, const Eigen::Vector2d& t);

  bool isFinite() const {
    return std::isfinite(yaw_rad) && std::isfinite(scale) && t_m.allFinite() &&
           std::isfinite(stretch) && std::isfinite(stretch_axis_rad);
  }

  std::string toString() const;
};

}  // namespace efs
