// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/sim2.h"

#include <gtest/gtest.h>

#include "efs_common/angles.h"

namespace efs {
namespace {

TEST(Sim2, AppliesScaleRotationTranslationInThatOrder) {
  const Sim2 t(M_PI / 2, 2.0, Eigen::Vector2d(10, 20));
  const Eigen::Vector2d q = t.apply(Eigen::Vector2d(1, 0));
  EXPECT_NEAR(q.x(), 10.0, 1e-12);
  EXPECT_NEAR(q.y(), 22.0, 1e-12);
}

TEST(Sim2, InverseUndoesTransform) {
  const Sim2 t(0.7, 0.35, Eigen::Vector2d(-3, 4.5));
  const Eigen::Vector2d p(2.5, -1.25);
  const Eigen::Vector2d back = t.inverse().apply(t.apply(p));
  EXPECT_NEAR((back - p).norm(), 0.0, 1e-12);
  EXPECT_NEAR(t.inverse().scale, 1.0 / 0.35, 1e-12);
}

TEST(Sim2, CompositionMatchesSequentialApplication) {
  const Sim2 a(0.3, 1.5, Eigen::Vector2d(1, 2));
  const Sim2 b(-1.1, 0.8, Eigen::Vector2d(-4, 0.5));
  const Eigen::Vector2d p(0.7, -2.0);
  EXPECT_NEAR(((a * b).apply(p) - a.apply(b.apply(p))).norm(), 0.0, 1e-12);
}

TEST(Sim2, FromLinearRecoversParametersIncludingReflection) {
  for (bool reflect : {false, true}) {
    const Sim2 t(2.9, 3.25, Eigen::Vector2d(7, -8), reflect);
    const Sim2 r = Sim2::fromLinear(t.linear(), t.t_m);
    EXPECT_EQ(r.reflected, reflect);
    EXPECT_NEAR(r.scale, 3.25, 1e-12);
    EXPECT_NEAR(angleDiff(r.yaw_rad, 2.9), 0.0, 1e-12);
    EXPECT_NEAR((r.matrix() - t.matrix()).norm(), 0.0, 1e-12);
  }
}

TEST(Sim2, AStretchLengthensAlongItsAxisAndShortensAcrossKeepingArea) {
  Sim2 t(0.0, 1.0, Eigen::Vector2d::Zero());
  t.stretch = 1.1;
  t.stretch_axis_rad = M_PI / 6;
  const Eigen::Vector2d along(std::cos(M_PI / 6), std::sin(M_PI / 6));
  const Eigen::Vector2d across(-along.y(), along.x());
  EXPECT_NEAR((t.apply(along) - 1.1 * along).norm(), 0.0, 1e-12);
  EXPECT_NEAR((t.apply(across) - across / 1.1).norm(), 0.0, 1e-12);
  EXPECT_NEAR(t.linear().determinant(), 1.0, 1e-12);
  EXPECT_FALSE(t.isSimilarity());
}

TEST(Sim2, FromLinearRecoversAStretchWithAndWithoutReflection) {
  for (bool reflect : {false, true}) {
    Sim2 t(-2.2, 1.7, Eigen::Vector2d(3, 1), reflect);
    t.stretch = 1.08;
    t.stretch_axis_rad = 0.4;
    const Sim2 r = Sim2::fromLinear(t.linear(), t.t_m);
    EXPECT_EQ(r.reflected, reflect);
    EXPECT_NEAR(r.scale, 1.7, 1e-12);
    EXPECT_NEAR(angleDiff(r.yaw_rad, -2.2), 0.0, 1e-12);
    EXPECT_NEAR(r.stretch, 1.08, 1e-12);
    EXPECT_NEAR(angleDiff(2.0 * r.stretch_axis_rad, 0.8), 0.0, 1e-12);  // an axis, not a direction
    EXPECT_NEAR((r.matrix() - t.matrix()).norm(), 0.0, 1e-12);
  }
}

TEST(Sim2, AnyInvertibleLinearMapDecomposes) {
  Eigen::Matrix2d l;
  l << 1.3, -0.4, 0.9, 2.1;
  for (double sign : {1.0, -1.0}) {
    Eigen::Matrix2d m = l;
    m.col(1) *= sign;
    const Sim2 r = Sim2::fromLinear(m, Eigen::Vector2d(1, 2));
    EXPECT_EQ(r.reflected, sign < 0);
    EXPECT_GE(r.stretch, 1.0);
    EXPECT_NEAR((r.linear() - m).norm(), 0.0, 1e-12);
  }
}

TEST(Sim2, StretchedTransformsInvertAndCompose) {
  Sim2 a(0.3, 1.5, Eigen::Vector2d(1, 2));
  a.stretch = 1.05;
  a.stretch_axis_rad = -0.7;
  Sim2 b(-1.1, 0.8, Eigen::Vector2d(-4, 0.5), true);
  b.stretch = 1.2;
  b.stretch_axis_rad = 1.3;
  const Eigen::Vector2d p(0.7, -2.0);
  EXPECT_NEAR((a.inverse().apply(a.apply(p)) - p).norm(), 0.0, 1e-12);
  EXPECT_NEAR(((a * b).apply(p) - a.apply(b.apply(p))).norm(), 0.0, 1e-12);
  const Sim2 ab = a * b;
  EXPECT_NEAR((ab.inverse().apply(ab.apply(p)) - p).norm(), 0.0, 1e-12);
}

TEST(Sim2, ASimilarityComesBackWithoutStretch) {
  const Sim2 a(0.3, 1.5, Eigen::Vector2d(1, 2)), b(-1.1, 0.8, Eigen::Vector2d(-4, 0.5));
  EXPECT_TRUE((a * b).isSimilarity());
  EXPECT_TRUE(a.inverse().isSimilarity());
  EXPECT_EQ((a * b).stretch_axis_rad, 0.0);
}

TEST(Sim2, ApplyXYKeepsHeight) {
  const Sim2 t(1.0, 2.0, Eigen::Vector2d(1, 1));
  const Eigen::Vector3d q = t.applyXY(Eigen::Vector3d(1, 2, 3.5));
  EXPECT_DOUBLE_EQ(q.z(), 3.5);
}

TEST(Angles, WrapAngleIntoHalfOpenPiInterval) {
  EXPECT_NEAR(wrapAngle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(wrapAngle(-M_PI), M_PI, 1e-12);
  EXPECT_NEAR(wrapAngle(0.25 + 4 * M_PI), 0.25, 1e-12);
  EXPECT_NEAR(angleDiff(0.1, 2 * M_PI - 0.1), 0.2, 1e-12);
}

}  // namespace
}  // namespace efs
