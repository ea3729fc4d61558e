// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The 2D similarity transform that maps the sketch's metric frame into the world (LIO) frame:
//   p_world_xy = scale * R(yaw) * p_sketch + t.
// TF cannot carry scale, which is why this type (not a tf2 transform) travels between modules.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <string>

namespace efs {

/// 2D similarity transform: rotation by `yaw_rad`, uniform `scale`, then translation `t_m`.
/// Optionally a reflection about the source x axis is applied first (`reflected`), which is how a
/// mirror-image sketch is registered.
struct Sim2 {
  double yaw_rad = 0.0;
  double scale = 1.0;
  Eigen::Vector2d t_m = Eigen::Vector2d::Zero();
  bool reflected = false;

  Sim2() = default;
  Sim2(double yaw, double s, const Eigen::Vector2d& t, bool reflect = false)
      : yaw_rad(yaw), scale(s), t_m(t), reflected(reflect) {}

  static Sim2 identity() { return Sim2(); }

  /// The linear part s * R * F, where F = diag(1, -1) if reflected.
  Eigen::Matrix2d linear() const {
    const double c = std::cos(yaw_rad), sn = std::sin(yaw_rad);
    Eigen::Matrix2d a;
    a << c, -sn, sn, c;
    if (reflected) a.col(1) = -a.col(1);
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

  /// Decomposes a linear map that is a (possibly reflected) scaled rotation. The caller is
  /// responsible for `l` being of that form (least-squares fits produce it by construction).
  static Sim2 fromLinear(const Eigen::Matrix2d& l, const Eigen::Vector2d& t) {
    Sim2 out;
    const double det = l.determinant();
    out.reflected = det < 0.0;
    out.scale = std::sqrt(std::abs(det));
    Eigen::Matrix2d r = l / out.scale;
    if (out.reflected) r.col(1) = -r.col(1);
    out.yaw_rad = std::atan2(r(1, 0), r(0, 0));
    out.t_m = t;
    return out;
  }

  bool isFinite() const {
    return std::isfinite(yaw_rad) && std::isfinite(scale) && t_m.allFinite();
  }

  std::string toString() const;
};

}  // namespace efs
