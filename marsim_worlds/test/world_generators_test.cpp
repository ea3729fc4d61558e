// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/world_generators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "efs_common/config_check.h"
#include "plain_flood_fill.h"

namespace efs::sim {
namespace {

const WorldKind kKinds[] = {WorldKind::kGarage, WorldKind::kSimpleCave, WorldKind::kSubtCave,
                            WorldKind::kIndoor};

// Fraction of horizontal rays from the start that hit something within 60 m.
double enclosedFraction(const VoxelWorld& w) {
  const Eigen::Vector3d o = w.start_poses.front().position_m;
  int hits = 0;
  const int n = 72;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    hits += std::isfinite(w.castRay(o, {std::cos(a), std::sin(a), 0.0}, 60.0));
  }
  return static_cast<double>(hits) / n;
}

// Voxels of the exploration box the vehicle could occupy but cannot reach from the start: a voxel
// is passable when a sphere of `radius_m` at its centre is collision-free (radius 0: the voxel is
// free), and passable voxels connect to their 6 neighbours. Coverage's ground truth leaves out
// what a point cannot reach from the start (FreeSpaceComponent), not what only the vehicle
// cannot: behind a door narrower than the vehicle it would count surfaces no flight can see.
size_t unreachablePassableVoxels(const VoxelWorld& w, double radius_m) {
  const Eigen::Vector3d eps = Eigen::Vector3d::Constant(1e-9);
  const Eigen::Vector3i lo = w.voxelOf(w.bounds().min() + eps).cwiseMax(0);
  const Eigen::Vector3i hi =
      w.voxelOf(w.bounds().max() - eps).cwiseMin(w.dimsVoxels() - Eigen::Vector3i::Ones());
  auto passable = [&](const Eigen::Vector3i& v) {
    const Eigen::Vector3d c = w.voxelCenter(v);
    return radius_m > 0.0 ? !w.collides(c, radius_m) : !w.occupied(v) && w.bounds().contains(c);
  };
  const testing::FloodFillCount c =
      testing::plainFloodFill(lo, hi, w.voxelOf(w.start_poses.front().position_m), passable);
  return c.passable - c.reached;
}

TEST(WorldGenerators, ReachabilityCheckFindsAClosedRoomAndANarrowDoor) {
  // Two 2 x 2 x 2 m rooms side by side in solid, 0.3 m of wall between them; the start is in
  // the west room. The check must see the east room as closed, then as too narrow, then open.
  VoxelWorld w(Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(6.0, 3.0, 3.0)), 0.1,
               VoxelWorld::Fill::kSolid);
  w.fillBox({Eigen::Vector3d(0.5, 0.5, 0.5), Eigen::Vector3d(2.5, 2.5, 2.5)}, false);
  w.fillBox({Eigen::Vector3d(2.8, 0.5, 0.5), Eigen::Vector3d(4.8, 2.5, 2.5)}, false);
  w.start_poses = {{Eigen::Vector3d(1.5, 1.5, 1.5), 0.0}};
  const size_t room_voxels = 20 * 20 * 20;
  EXPECT_EQ(unreachablePassableVoxels(w, 0.0), room_voxels);
  EXPECT_GT(unreachablePassableVoxels(w, 0.25), 0u);
  // A 0.3 m slot: a point passes, a 0.25 m sphere does not.
  w.fillBox({Eigen::Vector3d(2.5, 1.35, 0.5), Eigen::Vector3d(2.8, 1.65, 2.5)}, false);
  EXPECT_EQ(unreachablePassableVoxels(w, 0.0), 0u);
  EXPECT_GT(unreachablePassableVoxels(w, 0.25), 0u);
  // A 1 m door opens it for the vehicle too.
  w.fillBox({Eigen::Vector3d(2.5, 1.0, 0.5), Eigen::Vector3d(2.8, 2.0, 2.5)}, false);
  EXPECT_EQ(unreachablePassableVoxels(w, 0.25), 0u);
}

TEST(WorldGenerators, EveryRoomOfTheBuildingsHasADoorTheVehicleFitsThrough) {
  // Issue 8 suspected doorless rooms; none were found on the paper indoor world (seed 1). This
  // keeps it so for the buildings, over several seeds, at the resolution the missions use.
  const double vehicle_radius_m = 0.25;  // SimulatorConfig::vehicle_radius_m
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    SCOPED_TRACE("indoor seed " + std::to_string(seed));
    const VoxelWorld w = generateWorld(WorldKind::kIndoor, WorldSize::kSmall, seed, 0.15);
    EXPECT_EQ(unreachablePassableVoxels(w, 0.0), 0u);
    EXPECT_EQ(unreachablePassableVoxels(w, vehicle_radius_m), 0u);
  }
  const VoxelWorld g = generateWorld(WorldKind::kGarage, WorldSize::kSmall, 1, 0.15);
  EXPECT_EQ(unreachablePassableVoxels(g, 0.0), 0u);
  EXPECT_EQ(unreachablePassableVoxels(g, vehicle_radius_m), 0u);
}

TEST(WorldGenerators, SmallWorldsAreAbout40mAcrossWithAValidStart) {
  for (WorldKind kind : kKinds) {
    const VoxelWorld w = generateWorld(kind, WorldSize::kSmall, 1, 0.2);
    SCOPED_TRACE(worldKindName(kind));
    EXPECT_EQ(w.name, worldKindName(kind));
    const Eigen::Vector3d size = w.bounds().sizes();
    EXPECT_GE(size.head<2>().maxCoeff(), 35.0);
    EXPECT_LE(size.head<2>().maxCoeff(), 50.0);
    ASSERT_EQ(w.start_poses.size(), 1u);
    EXPECT_NO_THROW(w.validateStartPoses(1.0));
    EXPECT_GE(w.clearance(w.start_poses[0].position_m, 2.0), 1.0);
    // Closed worlds: every horizontal ray from the start ends on a wall.
    EXPECT_DOUBLE_EQ(enclosedFraction(w), 1.0);
    // Neither solid nor empty: a sensible share of the box is free.
    const double voxels = static_cast<double>(w.dimsVoxels().prod());
    const double free_share = 1.0 - w.occupiedVoxelCount() / voxels;
    EXPECT_GT(free_share, 0.03);
    EXPECT_LT(free_share, 0.95);
  }
}

TEST(WorldGenerators, SameSeedSameWorldOtherSeedOtherWorld) {
  for (WorldKind kind : kKinds) {
    SCOPED_TRACE(worldKindName(kind));
    const VoxelWorld a = generateWorld(kind, WorldSize::kSmall, 42, 0.2);
    const VoxelWorld b = generateWorld(kind, WorldSize::kSmall, 42, 0.2);
    const VoxelWorld c = generateWorld(kind, WorldSize::kSmall, 43, 0.2);
    EXPECT_EQ(a.fingerprint(), b.fingerprint());
    EXPECT_EQ(a.start_poses[0].position_m, b.start_poses[0].position_m);
    EXPECT_NE(a.fingerprint(), c.fingerprint());
  }
}

TEST(WorldGenerators, CavesBranchAndChangeHeight) {
  // The SubT-like network has junctions: from the start, free space extends in many directions.
  CaveConfig cfg = CaveConfig::subt(WorldSize::kSmall);
  cfg.resolution_m = 0.2;
  const VoxelWorld w = generateCave(cfg);
  // Free voxels exist at clearly different heights in the simple cave.
  CaveConfig simple = CaveConfig::simple(WorldSize::kSmall);
  simple.resolution_m = 0.25;
  const VoxelWorld s = generateCave(simple);
  int z_min = s.dimsVoxels().z(), z_max = 0;
  for (int x = 0; x < s.dimsVoxels().x(); x += 4) {
    for (int z = 0; z < s.dimsVoxels().z(); ++z) {
      for (int y = 0; y < s.dimsVoxels().y(); y += 2) {
        if (!s.occupied({x, y, z}) && s.bounds().contains(s.voxelCenter({x, y, z}))) {
          z_min = std::min(z_min, z);
          z_max = std::max(z_max, z);
        }
      }
    }
  }
  EXPECT_GT((z_max - z_min) * simple.resolution_m, 6.0);
  EXPECT_GT(w.maskedBrickCount(), 100u);
}

TEST(WorldGenerators, AbsurdParametersAreNamed) {
  CaveConfig cave = CaveConfig::subt(WorldSize::kSmall);
  cave.tunnel_radius_m = -1.0;
  try {
    generateCave(cave);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("tunnel_radius_m"), std::string::npos);
  }
  GarageConfig garage = GarageConfig::preset(WorldSize::kSmall);
  garage.car_probability = 1.5;
  EXPECT_THROW(generateGarage(garage), ConfigError);
  IndoorConfig indoor = IndoorConfig::preset(WorldSize::kSmall);
  indoor.size_m.x() = std::nan("");
  try {
    generateIndoor(indoor);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("size_m"), std::string::npos);
  }
  EXPECT_THROW(parseWorldKind("castle"), std::invalid_argument);
  EXPECT_EQ(parseWorldKind("subt_cave"), WorldKind::kSubtCave);
}

}  // namespace
}  // namespace efs::sim
