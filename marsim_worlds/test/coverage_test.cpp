// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/coverage.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "efs_common/config_check.h"
#include "marsim_worlds/analytic_worlds.h"

namespace efs::sim {
namespace {

// A room whose walls pass through voxel centres (0.3 m voxels): x, y in voxels -7..6, z in 0..8,
// so every surface voxel holds a full half-voxel patch of wall and none is a sliver.
AnalyticBoxWorld alignedRoom() {
  return AnalyticBoxWorld(
      Eigen::AlignedBox3d(Eigen::Vector3d(-1.95, -1.95, 0.15), Eigen::Vector3d(1.95, 1.95, 2.55)));
}

TEST(Coverage, SurfaceVoxelKeyPutsBoundaryHitsBehindTheSurface) {
  const VoxelKey k =
      surfaceVoxelKey(Eigen::Vector3f(3.0f, 0.1f, 0.1f), Eigen::Vector3f::UnitX(), 0.3);
  EXPECT_EQ(k.x, 10);
  const VoxelKey k2 =
      surfaceVoxelKey(Eigen::Vector3f(3.0f, 0.1f, 0.1f), -Eigen::Vector3f::UnitX(), 0.3);
  EXPECT_EQ(k2.x, 9);
}

TEST(Coverage, ObservableSurfaceOfAClosedRoomIsItsWallVoxels) {
  const AnalyticBoxWorld room = alignedRoom();
  ObservableSurfaceConfig c;
  c.rays_per_point = 200000;
  const VoxelKeySet keys = observableSurfaceKeys(room, {Eigen::Vector3d(0.0, 0.0, 1.35)}, c);
  // The shell of the 14 x 14 x 9 block of voxels that the room cuts.
  const int shell = 14 * 14 * 9 - 12 * 12 * 7;
  EXPECT_EQ(static_cast<int>(keys.size()), shell);
  for (const VoxelKey& k : keys) {
    const bool on_shell = k.x == -7 || k.x == 6 || k.y == -7 || k.y == 6 || k.z == 0 || k.z == 8;
    EXPECT_TRUE(on_shell) << k.x << " " << k.y << " " << k.z;
  }
  // Sample points that collide are skipped.
  EXPECT_TRUE(observableSurfaceKeys(room, {Eigen::Vector3d(1.9, 0.0, 1.35)}, c).empty());
}

TEST(Coverage, FractionCountsGroundTruthVoxelsOnceAndIgnoresOthers) {
  VoxelKeySet gt;
  for (int i = 0; i < 10; ++i) gt.insert(VoxelKey{i, 0, 0});
  CoverageConfig cc;
  cc.coverage_range_m = 5.0;
  Coverage cov(cc, gt);
  EXPECT_EQ(cov.totalVoxels(), 10u);
  EXPECT_EQ(cov.fraction(), 0.0);
  const Eigen::Vector3f d = Eigen::Vector3f::UnitZ();
  // Voxel 0 twice, voxel 1, a voxel outside the ground truth, voxel 9 out of range.
  std::vector<Eigen::Vector3f> pts = {{0.1f, 0.1f, 0.1f},
                                      {0.2f, 0.1f, 0.1f},
                                      {0.4f, 0.1f, 0.1f},
                                      {0.1f, 5.0f, 0.1f},
                                      {2.8f, 0.1f, 0.1f}};
  std::vector<Eigen::Vector3f> dirs(pts.size(), d);
  EXPECT_EQ(cov.observe(Eigen::Vector3d(-3.0, 0.1, 0.1), pts, dirs), 2u);
  EXPECT_EQ(cov.seenVoxels(), 2u);
  EXPECT_NEAR(cov.fraction(), 0.2, 1e-12);
  EXPECT_TRUE(cov.isSeen({0, 0, 0}));
  EXPECT_FALSE(cov.isSeen({9, 0, 0}));
  EXPECT_EQ(cov.observe(Eigen::Vector3d(-3.0, 0.1, 0.1), pts, dirs), 0u);  // monotone, no recount
  EXPECT_FALSE(cov.finished());
}

// The unseen surface of a closed room, sorted and told apart by the way it faces; a seen voxel
// leaves it.
TEST(Coverage, GapsAreTheUnseenSurfaceByFacing) {
  const AnalyticBoxWorld room = alignedRoom();
  ObservableSurfaceConfig oc;
  oc.rays_per_point = 200000;
  const VoxelKeySet gt = observableSurfaceKeys(room, {Eigen::Vector3d(0.0, 0.0, 1.35)}, oc);
  Coverage cov(CoverageConfig{}, gt);
  EXPECT_EQ(surfaceFacing(room, {0, 0, 0}, 0.3), SurfaceFacing::kUp);
  EXPECT_EQ(surfaceFacing(room, {0, 0, 8}, 0.3), SurfaceFacing::kDown);
  EXPECT_EQ(surfaceFacing(room, {-7, 0, 4}, 0.3), SurfaceFacing::kSideways);
  EXPECT_EQ(surfaceFacing(room, {6, 3, 4}, 0.3), SurfaceFacing::kSideways);

  CoverageGaps g = coverageGaps(cov, room);
  ASSERT_EQ(g.unseen.size(), gt.size());
  ASSERT_EQ(g.facing.size(), gt.size());
  EXPECT_TRUE(std::is_sorted(g.unseen.begin(), g.unseen.end(), voxelKeyLess));
  EXPECT_EQ(g.up + g.down + g.sideways, gt.size());
  EXPECT_EQ(g.total_up, g.up);
  EXPECT_EQ(g.total_down, g.down);
  EXPECT_EQ(g.total_sideways, g.sideways);
  // The floor's and the ceiling's 12 x 12 inner voxels at least, at most with the walls' rim
  // along them (corner voxels hold both surfaces); the walls between floor and ceiling rows.
  EXPECT_GE(g.up, 12u * 12u);
  EXPECT_LE(g.up, 14u * 14u + 4u * 13u);
  EXPECT_GE(g.down, 12u * 12u);
  EXPECT_LE(g.down, 14u * 14u + 4u * 13u);
  EXPECT_GE(g.sideways, 4u * 12u * 5u);
  EXPECT_DOUBLE_EQ(g.voxel_size_m, 0.3);

  const std::vector<Eigen::Vector3f> hit = {{0.1f, 0.1f, 0.15f}};
  const std::vector<Eigen::Vector3f> down = {-Eigen::Vector3f::UnitZ()};
  ASSERT_EQ(cov.observe(Eigen::Vector3d(0.1, 0.1, 1.35), hit, down), 1u);
  g = coverageGaps(cov, room);
  EXPECT_EQ(g.unseen.size(), gt.size() - 1);
  EXPECT_EQ(g.up, g.total_up - 1);
  EXPECT_EQ(g.down, g.total_down);
  EXPECT_FALSE(
      std::binary_search(g.unseen.begin(), g.unseen.end(), VoxelKey{0, 0, 0}, voxelKeyLess));
}

TEST(Coverage, FreeSamplePointsKeepClearance) {
  const AnalyticBoxWorld room = makeRoomWithPillar({6.0, 6.0, 3.0}, 0.0, 0.0, 1.0);
  const auto pts = freeSamplePoints(room, room.bounds(), 0.5, 0.4);
  EXPECT_FALSE(pts.empty());
  for (const auto& p : pts) EXPECT_GE(room.distanceToSurface(p), 0.4);
}

TEST(Coverage, BadConfigNamesTheKey) {
  CoverageConfig c;
  c.voxel_size_m = 0.0;
  try {
    Coverage cov(c, {});
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("voxel_size_m"), std::string::npos);
  }
  ObservableSurfaceConfig o;
  o.rays_per_point = 0;
  EXPECT_THROW(o.validate(), ConfigError);
}

}  // namespace
}  // namespace efs::sim
