// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/analytic_worlds.h"

#include <gtest/gtest.h>

#include <cmath>

namespace efs::sim {
namespace {

TEST(AnalyticBoxWorld, RayFromInsideHitsTheFarWallAtTheClosedFormRange) {
  const AnalyticBoxWorld w = makeBoxRoom({10.0, 6.0, 3.0});  // x [-5,5], y [-3,3], z [0,3]
  const Eigen::Vector3d o(1.0, 0.5, 1.0);
  EXPECT_NEAR(w.castRay(o, Eigen::Vector3d::UnitX(), 100.0), 4.0, 1e-12);
  EXPECT_NEAR(w.castRay(o, -Eigen::Vector3d::UnitY(), 100.0), 3.5, 1e-12);
  EXPECT_NEAR(w.castRay(o, -Eigen::Vector3d::UnitZ(), 100.0), 1.0, 1e-12);
  // Diagonal in x-z: hits the ceiling (z = 3) after 2 / sin(45 deg).
  const Eigen::Vector3d d = Eigen::Vector3d(1, 0, 1).normalized();
  EXPECT_NEAR(w.castRay(o, d, 100.0), 2.0 * std::sqrt(2.0), 1e-12);
  // Beyond the max range: no hit.
  EXPECT_TRUE(std::isinf(w.castRay(o, Eigen::Vector3d::UnitX(), 3.9)));
}

TEST(AnalyticBoxWorld, PillarOccludesTheWallBehindIt) {
  const AnalyticBoxWorld w = makeRoomWithPillar({10.0, 10.0, 3.0}, 2.0, 0.0, 1.0);
  const Eigen::Vector3d o(0.0, 0.0, 1.0);
  EXPECT_NEAR(w.castRay(o, Eigen::Vector3d::UnitX(), 100.0), 1.5, 1e-12);
  EXPECT_NEAR(w.castRay(o, -Eigen::Vector3d::UnitX(), 100.0), 5.0, 1e-12);
  // Batch interface agrees with the single ray and marks misses as kNoHit.
  std::vector<float> r;
  w.castRays(o, {Eigen::Vector3f::UnitX(), -Eigen::Vector3f::UnitX()}, 4.0, &r);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_NEAR(r[0], 1.5f, 1e-6f);
  EXPECT_EQ(r[1], WorldGeometry::kNoHit);
}

TEST(AnalyticBoxWorld, CollidesNearWallsAndPillarsOnly) {
  const AnalyticBoxWorld w = makeRoomWithPillar({10.0, 10.0, 3.0}, 2.0, 0.0, 1.0);
  EXPECT_FALSE(w.collides({0.0, 0.0, 1.5}, 0.3));
  EXPECT_TRUE(w.collides({4.8, 0.0, 1.5}, 0.3));  // wall at x = 5
  EXPECT_TRUE(w.collides({0.0, 0.0, 0.2}, 0.3));  // floor
  EXPECT_TRUE(w.collides({1.3, 0.0, 1.5}, 0.3));  // pillar face at x = 1.5
  EXPECT_FALSE(w.collides({1.1, 0.0, 1.5}, 0.3));
  EXPECT_TRUE(w.collides({20.0, 0.0, 1.5}, 0.3));  // outside the bounds
  EXPECT_TRUE(w.collides({NAN, 0.0, 1.5}, 0.3));
  EXPECT_NEAR(w.distanceToSurface({1.0, 0.0, 1.5}), 0.5, 1e-12);
}

TEST(AnalyticBoxWorld, PillarHallHasARegularGridAndRejectsBadSpacing) {
  const AnalyticBoxWorld w = makePillarHall({40.0, 30.0, 4.0}, 8.0, 0.6);
  EXPECT_EQ(w.solidBoxes().size(), 4u * 3u);
  EXPECT_THROW(makePillarHall({40.0, 30.0, 4.0}, 0.5, 0.6), std::invalid_argument);
  EXPECT_THROW(
      AnalyticBoxWorld(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 1))),
      std::invalid_argument);
}

}  // namespace
}  // namespace efs::sim
