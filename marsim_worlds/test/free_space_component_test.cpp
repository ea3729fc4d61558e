// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/free_space_component.h"

#include <gtest/gtest.h>

#include <limits>

#include "marsim_worlds/coverage.h"
#include "marsim_worlds/simulation_session.h"
#include "plain_flood_fill.h"

namespace efs::sim {
namespace {

using Box = Eigen::AlignedBox3d;
using V3 = Eigen::Vector3d;

// Solid rock with room A (x in [-7, -1]) and room B (x in [1, 7]), both 6 x 6 x 3 m, the 2 m of
// rock between them optionally pierced by a door. Bounds off the 1.6 m brick grid, so the fill
// crosses free, full and cut bricks.
VoxelWorld twoRooms(bool door) {
  VoxelWorld w(Box(V3(-8.3, -4.1, -1.1), V3(8.2, 4.3, 4.1)), 0.2, VoxelWorld::Fill::kSolid);
  w.fillBox(Box(V3(-7, -3, 0), V3(-1, 3, 3)), false);
  w.fillBox(Box(V3(1, -3, 0), V3(7, 3, 3)), false);
  if (door) w.fillBox(Box(V3(-1.1, -0.35, 0), V3(1.1, 0.35, 2)), false);
  w.compact();
  w.start_poses = {StartPose{V3(-4, 0, 1.5), 0.0}};
  return w;
}

// The plain voxel-by-voxel flood fill over the whole grid, the reference to match.
std::size_t referenceCount(const VoxelWorld& w, const V3& seed) {
  return testing::plainFloodFill(Eigen::Vector3i::Zero(), w.dimsVoxels() - Eigen::Vector3i::Ones(),
                                 w.voxelOf(seed),
                                 [&](const Eigen::Vector3i& v) { return !w.occupied(v); })
      .reached;
}

TEST(FreeSpaceComponent, ASealedRoomIsNotReachedAndADoorJoinsIt) {
  const VoxelWorld sealed = twoRooms(false);
  const FreeSpaceComponent a(sealed, V3(-4, 0, 1.5));
  EXPECT_TRUE(a.contains(V3(-6.9, 2.9, 0.1)));
  EXPECT_TRUE(a.contains(V3(-1.1, -2.9, 2.9)));
  EXPECT_FALSE(a.contains(V3(4, 0, 1.5)));
  EXPECT_FALSE(a.contains(V3(0, 0, 1)));     // rock
  EXPECT_FALSE(a.contains(V3(40, 0, 1.5)));  // outside the grid
  // Every cell the 6 x 6 x 3 m box touches: its faces fall mid-voxel, so 31 x 31 x 16.
  EXPECT_EQ(a.voxelCount(), static_cast<size_t>(31 * 31 * 16));
  EXPECT_EQ(a.voxelCount(), referenceCount(sealed, V3(-4, 0, 1.5)));

  const VoxelWorld joined = twoRooms(true);
  const FreeSpaceComponent both(joined, V3(-4, 0, 1.5));
  EXPECT_TRUE(both.contains(V3(4, 0, 1.5)));
  EXPECT_TRUE(both.contains(V3(0, 0, 1)));  // in the door
  EXPECT_FALSE(both.contains(V3(0, 2, 1)));
  EXPECT_EQ(both.voxelCount(), referenceCount(joined, V3(-4, 0, 1.5)));
  EXPECT_GT(both.voxelCount(), 2 * a.voxelCount());
}

TEST(FreeSpaceComponent, BrickWiseFillMatchesTheVoxelFillInAFreeGridWithAPillar) {
  // Mostly all-free bricks, one pillar cutting some, the grid's own border as the only wall.
  VoxelWorld w(Box(V3(0, 0, 0), V3(9.6, 6.4, 3.2)), 0.2);
  w.fillBox(Box(V3(3.1, 2.1, 0), V3(3.9, 2.7, 3.2)), true);
  w.compact();
  const FreeSpaceComponent c(w, V3(8, 5, 1));
  EXPECT_EQ(c.voxelCount(), referenceCount(w, V3(8, 5, 1)));
  EXPECT_TRUE(c.contains(V3(0.05, 0.05, 0.05)));
  EXPECT_FALSE(c.contains(V3(3.5, 2.4, 1)));
}

TEST(FreeSpaceComponent, ASeedInRockOutsideTheGridOrNotFiniteReachesNothing) {
  const VoxelWorld w = twoRooms(true);
  EXPECT_EQ(FreeSpaceComponent(w, V3(0, 2, 1)).voxelCount(), 0u);
  EXPECT_FALSE(FreeSpaceComponent(w, V3(0, 2, 1)).contains(V3(-4, 0, 1.5)));
  EXPECT_EQ(FreeSpaceComponent(w, V3(100, 0, 1)).voxelCount(), 0u);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(FreeSpaceComponent(w, V3(nan, 0, 1)).voxelCount(), 0u);
  const FreeSpaceComponent c(w, V3(-4, 0, 1.5));
  EXPECT_FALSE(c.contains(V3(-4, nan, 1.5)));
  EXPECT_FALSE(c.contains(V3(std::numeric_limits<double>::infinity(), 0, 1.5)));
}

TEST(FreeSpaceComponent, CoverageCountsNothingOfASealedRoom) {
  SimulationSessionConfig config;
  config.sim.lidar_enabled = false;
  // Room A alone, and room A beside a sealed room B: the same ground truth.
  VoxelWorld alone = twoRooms(false);
  alone.fillBox(Box(V3(1, -3, 0), V3(7, 3, 3)), true);
  alone.compact();
  const SimulationSession one(config, std::move(alone));
  const SimulationSession two(config, twoRooms(false));
  ASSERT_NE(two.simulator().coverage(), nullptr);
  EXPECT_GT(one.simulator().coverage()->totalVoxels(), 500u);
  EXPECT_EQ(two.simulator().coverage()->totalVoxels(), one.simulator().coverage()->totalVoxels());
  EXPECT_EQ(two.coverageSamplesReachable(), one.coverageSamplesReachable());
  EXPECT_GT(two.coverageSamplesTotal(), two.coverageSamplesReachable());
  // With the door, B's walls count too.
  const SimulationSession joined(config, twoRooms(true));
  EXPECT_GT(joined.simulator().coverage()->totalVoxels(),
            one.simulator().coverage()->totalVoxels() * 3 / 2);
  EXPECT_EQ(joined.coverageSamplesReachable(), joined.coverageSamplesTotal());
}

}  // namespace
}  // namespace efs::sim
