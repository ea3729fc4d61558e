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
