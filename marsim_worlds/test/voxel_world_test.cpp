// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/voxel_world.h"

#include <gtest/gtest.h>

#include <cmath>

#include "efs_common/config_check.h"
#include "marsim_worlds/seeded_random.h"

namespace efs::sim {
namespace {

// A closed box room: interior [0,10]x[0,8]x[0,3] m free, walls 0.3 m thick all around.
VoxelWorld boxRoom(double res) {
  const Eigen::AlignedBox3d outer(Eigen::Vector3d(-0.3, -0.3, -0.3),
                                  Eigen::Vector3d(10.3, 8.3, 3.3));
  VoxelWorld w(outer, res, VoxelWorld::Fill::kSolid);
  w.fillBox(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 8, 3)), false);
  w.setExplorationBox(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 8, 3)));
  return w;
}

// Distance from a point inside the room to the nearest wall plane.
double distanceToRoomWall(const Eigen::Vector3d& p) {
  return std::min({std::abs(p.x()), std::abs(p.x() - 10.0), std::abs(p.y()), std::abs(p.y() - 8.0),
                   std::abs(p.z()), std::abs(p.z() - 3.0)});
}

TEST(VoxelWorld, EveryReturnInABoxRoomLiesOnAWall) {
  for (double res : {0.1, 0.15, 0.2}) {
    const VoxelWorld w = boxRoom(res);
    SeededRandom rng(7);
    std::vector<Eigen::Vector3f> dirs;
    for (int i = 0; i < 2000; ++i) {
      Eigen::Vector3f d(static_cast<float>(rng.normal()), static_cast<float>(rng.normal()),
                        static_cast<float>(rng.normal()));
      dirs.push_back(d.normalized());
    }
    for (const Eigen::Vector3d& origin :
         {Eigen::Vector3d(5, 4, 1.5), Eigen::Vector3d(1.03, 7.21, 0.4)}) {
      std::vector<float> ranges;
      w.castRays(origin, dirs, 40.0, &ranges);
      ASSERT_EQ(ranges.size(), dirs.size());
      for (size_t i = 0; i < dirs.size(); ++i) {
        ASSERT_TRUE(std::isfinite(ranges[i])) << "ray " << i << " escaped a closed room";
        const Eigen::Vector3d hit = origin + dirs[i].cast<double>() * ranges[i];
        // The grid is aligned to the walls, so a return lies on the wall plane to float precision;
        // allow one voxel as the contract.
        EXPECT_LT(distanceToRoomWall(hit), res) << "res " << res << " ray " << i;
      }
    }
  }
}

TEST(VoxelWorld, AxisAlignedRayHitsTheExactWallDistance) {
  const VoxelWorld w = boxRoom(0.1);
  EXPECT_NEAR(w.castRay({5, 4, 1.5}, {1, 0, 0}, 40.0), 5.0, 1e-4);
  EXPECT_NEAR(w.castRay({5, 4, 1.5}, {0, -1, 0}, 40.0), 4.0, 1e-4);
  EXPECT_NEAR(w.castRay({5, 4, 1.5}, {0, 0, 1}, 40.0), 1.5, 1e-4);
  // Beyond the maximum range there is no return.
  EXPECT_EQ(w.castRay({5, 4, 1.5}, {1, 0, 0}, 4.9), WorldGeometry::kNoHit);
  // Degenerate input is a miss, never a hang or a crash.
  EXPECT_EQ(w.castRay({5, 4, 1.5}, {0, 0, 0}, 40.0), WorldGeometry::kNoHit);
  EXPECT_EQ(w.castRay({5, 4, 1.5}, {std::nan(""), 0, 0}, 40.0), WorldGeometry::kNoHit);
  EXPECT_EQ(w.castRay({5, 4, 1.5}, {1, 0, 0}, std::nan("")), WorldGeometry::kNoHit);
}

TEST(VoxelWorld, RaysCrossLongEmptyStretchesAndThinObstacles) {
  // 100 m of free space with a one-voxel-thin slanted plate: the brick skipping must not skip it.
  VoxelWorld w(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(100, 20, 10)), 0.2);
  for (int y = 0; y < w.dimsVoxels().y(); ++y) {
    for (int z = 0; z < w.dimsVoxels().z(); ++z) {
      w.setVoxel({400 + y / 4, y, z}, true);
      if (y % 4 == 3) w.setVoxel({401 + y / 4, y, z}, true);  // 6-connected: no diagonal gaps
    }
  }
  SeededRandom rng(3);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d o(rng.uniform(65, 78), rng.uniform(3, 17), rng.uniform(3, 7));
    const Eigen::Vector3d d =
        Eigen::Vector3d(1.0, rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1)).normalized();
    const float r = w.castRay(o, d, 200.0);
    ASSERT_TRUE(std::isfinite(r));
    // The return lies on the face of an occupied voxel.
    EXPECT_LT(w.clearance(o + d * r, 0.5), 1e-3) << "ray " << i << " stopped in free space";
  }
  // Leaving the grid is a miss, not a hit.
  EXPECT_EQ(w.castRay({50, 10, 5}, {0, 0, 1}, 40.0), WorldGeometry::kNoHit);
}

TEST(VoxelWorld, RayFromOutsideTheGridEntersIt) {
  const VoxelWorld w = boxRoom(0.2);
  // From 5 m west of the outer wall, looking east: hits the outer face at x = -0.3 (voxel-aligned
  // to the grid origin).
  EXPECT_NEAR(w.castRay({-5.3, 4.1, 1.5}, {1, 0, 0}, 40.0), 5.0, 1e-4);
}

TEST(VoxelWorld, CollidesWithSpheresNearWallsAndOutsideBounds) {
  const VoxelWorld w = boxRoom(0.1);
  EXPECT_FALSE(w.collides({5, 4, 1.5}, 0.5));
  EXPECT_FALSE(w.collides({0.45, 4, 1.5}, 0.4));
  // A sphere reaching past a wall plane leaves the exploration box and touches the wall.
  EXPECT_TRUE(w.collides({0.35, 4, 1.5}, 0.4));
  EXPECT_TRUE(w.collides({5, 4, 2.9}, 0.2));
  EXPECT_TRUE(w.collides({-1, 4, 1.5}, 0.1));
  EXPECT_TRUE(w.collides({5, 4, std::nan("")}, 0.1));
  // An obstacle in the middle of the room.
  VoxelWorld w2 = boxRoom(0.1);
  w2.fillBox(Eigen::AlignedBox3d(Eigen::Vector3d(4, 4, 0), Eigen::Vector3d(5, 5, 3)), true);
  EXPECT_TRUE(w2.collides({5.25, 4.5, 1.0}, 0.3));
  EXPECT_FALSE(w2.collides({5.45, 4.5, 1.0}, 0.4));
  EXPECT_TRUE(w2.collides({4.5, 4.5, 1.0}, 0.01));
}

TEST(VoxelWorld, SolidInteriorStaysSolidAndCostsNoMasks) {
  VoxelWorld w(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(16, 16, 16)), 0.1,
               VoxelWorld::Fill::kSolid);
  EXPECT_EQ(w.maskedBrickCount(), 0u);
  EXPECT_TRUE(w.occupiedAt({8, 8, 8}));
  w.fillBox(Eigen::AlignedBox3d(Eigen::Vector3d(4.25, 4, 4), Eigen::Vector3d(12, 12, 12)), false);
  EXPECT_FALSE(w.occupiedAt({8, 8, 8}));
  // Every voxel whose cell overlaps the box is set: the cell [4.2, 4.3) is carved too.
  EXPECT_TRUE(w.occupiedAt({4.15, 8, 8}));
  EXPECT_FALSE(w.occupiedAt({4.21, 8, 8}));
  EXPECT_GT(w.maskedBrickCount(), 0u);
  const size_t occupied_before = w.occupiedVoxelCount();
  w.compact();
  EXPECT_EQ(w.occupiedVoxelCount(), occupied_before);
  // Only the boundary bricks of the carved box hold masks after compaction.
  const size_t all_bricks = 20u * 20u * 20u;
  EXPECT_LT(w.maskedBrickCount(), all_bricks / 4);
  // A ray from inside rock returns 0; one inside the cavity reaches its wall.
  EXPECT_EQ(w.castRay({1, 1, 1}, {1, 0, 0}, 10.0), 0.0f);
  EXPECT_NEAR(w.castRay({8, 8, 8}, {-1, 0, 0}, 10.0), 8.0 - 4.2, 1e-4);
}

TEST(VoxelWorld, PaintClassifiesBricksWithoutChangingTheResult) {
  // Carving a sphere by brick classification gives the same voxels as a per-voxel test.
  VoxelWorld a(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(12, 12, 12)), 0.1,
               VoxelWorld::Fill::kSolid);
  const Eigen::Vector3d c(6, 6, 6);
  a.paint(a.gridBox(), false, 1.0, [&](const Eigen::Vector3d& p) { return (p - c).norm() - 4.0; });
  int mismatches = 0;
  for (int z = 0; z < a.dimsVoxels().z(); z += 3)
    for (int y = 0; y < a.dimsVoxels().y(); y += 3)
      for (int x = 0; x < a.dimsVoxels().x(); x += 3) {
        const Eigen::Vector3i v(x, y, z);
        const bool expect_free = (a.voxelCenter(v) - c).norm() < 4.0;
        mismatches += a.occupied(v) == expect_free;
      }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(a.fullBrickCount(), 0u);
}

TEST(VoxelWorld, StartPoseValidationNamesTheProblem) {
  VoxelWorld w = boxRoom(0.1);
  w.name = "room";
  EXPECT_THROW(w.validateStartPoses(0.5), std::invalid_argument);  // none
  w.start_poses = {{Eigen::Vector3d(5, 4, 1.5), 0.0}};
  EXPECT_NO_THROW(w.validateStartPoses(0.5));
  w.start_poses = {{Eigen::Vector3d(5, 4, 1.5), 0.0}, {Eigen::Vector3d(20, 4, 1.5), 0.0}};
  try {
    w.validateStartPoses(0.5);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("start pose 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("outside"), std::string::npos) << e.what();
  }
  w.fillBox(Eigen::AlignedBox3d(Eigen::Vector3d(4, 3, 0), Eigen::Vector3d(6, 5, 3)), true);
  w.start_poses = {{Eigen::Vector3d(5, 4, 1.5), 0.0}};
  try {
    w.validateStartPoses(0.5);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("inside an obstacle"), std::string::npos) << e.what();
  }
  EXPECT_NEAR(w.clearance({7.0, 4, 1.5}, 3.0), 1.0, 0.11);
}

TEST(VoxelWorld, AbsurdGridsAreRejectedByName) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 10, 10));
  EXPECT_THROW(VoxelWorld(box, 0.0), ConfigError);
  EXPECT_THROW(VoxelWorld(box, std::nan("")), ConfigError);
  EXPECT_THROW(VoxelWorld(Eigen::AlignedBox3d(), 0.1), ConfigError);
  try {
    VoxelWorld(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1e5, 1e5, 1e3)), 0.01);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("resolution_m"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace efs::sim
