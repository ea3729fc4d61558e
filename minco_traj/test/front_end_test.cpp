// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <queue>
#include <random>
#include <unordered_map>

#include "efs_common/config_check.h"
#include "minco_traj/astar.h"
#include "minco_traj/local_grid.h"

namespace efs::traj {
namespace {

LocalGridConfig smallGrid(double inflation = 0.0) {
  LocalGridConfig c;
  c.resolution_m = 0.1;
  c.size_x_m = 3.0;
  c.size_y_m = 3.0;
  c.size_z_m = 0.6;
  c.inflation_radius_m = inflation;
  return c;
}

/// Every key of g's window.
std::vector<VoxelKey> windowKeys(const LocalGrid& g) {
  const VoxelKey lo = g.minKey(), hi = g.maxKey();
  std::vector<VoxelKey> keys;
  for (int x = lo.x; x <= hi.x; ++x)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int z = lo.z; z <= hi.z; ++z) keys.push_back({x, y, z});
  return keys;
}

TEST(LocalGrid, RayCastingSeparatesFreeUnknownAndOccupied) {
  LocalGridConfig cfg = smallGrid(0.2);
  cfg.size_z_m = 2.0;
  LocalGrid g(cfg, Eigen::Vector3d(0, 0, 0));
  const Eigen::Vector3d origin(-1.0, 0.05, 0.05), hit(1.0, 0.05, 0.05);
  g.insertScan(origin, {hit});
  EXPECT_EQ(g.state(hit), CellState::kOccupied);
  EXPECT_EQ(g.state(Eigen::Vector3d(0.0, 0.05, 0.05)), CellState::kFree);
  EXPECT_EQ(g.state(Eigen::Vector3d(-0.5, 0.05, 0.05)), CellState::kFree);
  EXPECT_EQ(g.state(Eigen::Vector3d(0.0, 0.55, 0.05)), CellState::kUnknown);
  EXPECT_EQ(g.state(Eigen::Vector3d(10.0, 0, 0)), CellState::kOutside);
  // Inflation: cells within 0.2 m of the hit are blocked, farther ones are not.
  EXPECT_TRUE(g.isInflated(g.key(Eigen::Vector3d(0.85, 0.05, 0.05))));
  EXPECT_TRUE(g.isInflated(g.key(Eigen::Vector3d(1.05, 0.25, 0.05))));
  EXPECT_FALSE(g.isInflated(g.key(Eigen::Vector3d(0.65, 0.05, 0.05))));
  EXPECT_TRUE(g.isBlocked(g.key(Eigen::Vector3d(0.0, 0.55, 0.05)), false));  // unknown
  EXPECT_FALSE(g.isBlocked(g.key(Eigen::Vector3d(0.0, 0.55, 0.05)), true));
  EXPECT_EQ(g.occupiedCount(), 1u);
}

TEST(LocalGrid, RepeatedMissesClearAnObstacleAndItsInflation) {
  LocalGrid g(smallGrid(0.2), Eigen::Vector3d(0, 0, 0));
  const Eigen::Vector3d origin(-1.0, 0.05, 0.05), wall(0.5, 0.05, 0.05), far(1.2, 0.05, 0.05);
  g.insertScan(origin, {wall});
  ASSERT_EQ(g.state(wall), CellState::kOccupied);
  for (int i = 0; i < 20; ++i) g.insertScan(origin, {far});  // the obstacle moved away
  EXPECT_EQ(g.state(wall), CellState::kFree);
  EXPECT_FALSE(g.isInflated(g.key(Eigen::Vector3d(0.4, 0.05, 0.05))));
  EXPECT_EQ(g.state(far), CellState::kOccupied);
}

// A floor cell on the line of sight to a farther floor point: grazing rays cross it.
struct GrazingFloor {
  Eigen::Vector3d origin{-3.0, 0.05, 0.25};
  Eigen::Vector3d floor_cell{0.95, 0.05, -0.15};
  Eigen::Vector3d farther() const { return origin + 1.1 * (floor_cell - origin); }
};

TEST(LocalGrid, GrazingRaysDoNotEraseAnObservedFloor) {
  const GrazingFloor s;
  LocalGridConfig cfg = smallGrid();
  cfg.ray_downsample_m = 0.0;
  for (const bool weak_miss : {true, false}) {
    LocalGridConfig c = cfg;
    if (!weak_miss) c.logodds_miss_occupied = c.logodds_miss;  // the old behaviour, for contrast
    LocalGrid g(c, Eigen::Vector3d(0, 0, 0));
    g.insertScan(s.origin, {s.floor_cell});
    ASSERT_EQ(g.state(s.floor_cell), CellState::kOccupied);
    for (int i = 0; i < 6; ++i) g.insertScan(s.origin, {s.farther()});
    EXPECT_EQ(g.state(s.floor_cell), weak_miss ? CellState::kOccupied : CellState::kFree)
        << "weak miss on occupied cells: " << weak_miss;
  }
}

TEST(LocalGrid, AHitMakesACellOccupiedWhateverItsMisses) {
  const GrazingFloor s;
  LocalGridConfig cfg = smallGrid();
  cfg.ray_downsample_m = 0.0;
  for (const bool overrides : {true, false}) {
    LocalGridConfig c = cfg;
    c.hit_overrides_free = overrides;
    LocalGrid g(c, Eigen::Vector3d(0, 0, 0));
    for (int i = 0; i < 10; ++i) g.insertScan(s.origin, {s.farther()});  // seen through first
    ASSERT_EQ(g.state(s.floor_cell), CellState::kFree);
    g.insertScan(s.origin, {s.floor_cell});
    EXPECT_EQ(g.state(s.floor_cell), overrides ? CellState::kOccupied : CellState::kFree)
        << "hit overrides free: " << overrides;
  }
}

TEST(LocalGrid, OneRayPerCoarseEndVoxelButEveryHitCounts) {
  // Two returns 0.1 m apart in one 0.3 m voxel, on rays 0.2 rad apart.
  const Eigen::Vector3d origin(-1.0, 0.05, 0.05), a(1.05, 0.05, 0.05), b(1.05, 0.15, 0.05);
  LocalGridConfig cfg = smallGrid();
  cfg.ray_downsample_m = 0.3;
  LocalGrid coarse(cfg, Eigen::Vector3d(0, 0, 0));
  coarse.insertScan(origin, {a, b});
  EXPECT_EQ(coarse.state(a), CellState::kOccupied);
  EXPECT_EQ(coarse.state(b), CellState::kOccupied);
  EXPECT_EQ(coarse.state(Eigen::Vector3d(0.0, 0.05, 0.05)), CellState::kFree);  // a's ray
  cfg.ray_downsample_m = 0.0;
  LocalGrid fine(cfg, Eigen::Vector3d(0, 0, 0));
  fine.insertScan(origin, {a, b});
  // Cells that only b's ray crosses: cleared with a ray per point, left unknown otherwise.
  int only_fine = 0;
  for (double s = 0.55; s < 0.95; s += 0.02) {
    const Eigen::Vector3d p = origin + s * (b - origin);
    if (fine.state(p) == CellState::kFree && coarse.state(p) == CellState::kUnknown) ++only_fine;
    EXPECT_NE(coarse.state(p), CellState::kOccupied);
  }
  EXPECT_GT(only_fine, 0);
}

// Rays skip cells settled free (at logodds_min, where a miss changes nothing) without reading
// them; a hit, or a new key taking the slot, must end that.
TEST(LocalGrid, CellsSettledFreeStillChangeWhenHitOrReplaced) {
  LocalGridConfig cfg = smallGrid(0.1);
  cfg.ray_downsample_m = 0.0;
  cfg.memory_radius_m = 0.0;
  LocalGrid g(cfg, Eigen::Vector3d(0, 0, 0));
  const Eigen::Vector3d origin(-1.25, 0.05, 0.05), wall(1.25, 0.05, 0.05), mid(0.05, 0.05, 0.05);
  for (int i = 0; i < 10; ++i) g.insertScan(origin, {wall});  // settles the cells between
  ASSERT_EQ(g.state(mid), CellState::kFree);
  g.insertScan(origin, {mid});
  ASSERT_EQ(g.state(mid), CellState::kOccupied);
  EXPECT_TRUE(g.isInflated(g.key(Eigen::Vector3d(0.15, 0.05, 0.05))));
  // Weak misses (logodds_miss_occupied) from rays through it wear it down again.
  for (int i = 0; i < 30; ++i) g.insertScan(origin, {wall});
  EXPECT_EQ(g.state(mid), CellState::kFree);
  EXPECT_FALSE(g.isInflated(g.key(Eigen::Vector3d(0.15, 0.05, 0.05))));
  // A move by a whole window reuses every slot for keys never seen: unknown, then free once a
  // ray crosses them.
  g.recenter(Eigen::Vector3d(3.0, 0, 0));
  const Eigen::Vector3d new_mid(3.05, 0.05, 0.05);
  ASSERT_EQ(g.state(new_mid), CellState::kUnknown);
  g.insertScan(Eigen::Vector3d(1.75, 0.05, 0.05), {Eigen::Vector3d(4.25, 0.05, 0.05)});
  EXPECT_EQ(g.state(new_mid), CellState::kFree);
  EXPECT_EQ(g.state(Eigen::Vector3d(4.25, 0.05, 0.05)), CellState::kOccupied);
}

TEST(LocalGrid, RecenterForgetsOnlyCellsThatLeaveTheWindow) {
  LocalGridConfig cfg = smallGrid(0.1);
  cfg.memory_radius_m = 0.0;  // no surface memory: what leaves is gone
  LocalGrid g(cfg, Eigen::Vector3d(0, 0, 0));
  const Eigen::Vector3d keep(0.75, 0.05, 0.05), lose(-1.25, 0.05, 0.05);
  g.setOccupied(keep);
  g.setOccupied(lose);
  g.recenter(Eigen::Vector3d(1.0, 0, 0));
  EXPECT_EQ(g.state(keep), CellState::kOccupied);
  EXPECT_EQ(g.state(lose), CellState::kOutside);
  EXPECT_TRUE(g.isInflated(g.key(Eigen::Vector3d(0.85, 0.05, 0.05))));
  // New cells entering on the far side are unknown even though their ring slots were reused.
  EXPECT_EQ(g.state(Eigen::Vector3d(1.75, 0.05, 0.05)), CellState::kUnknown);
  g.recenter(Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(g.state(lose), CellState::kUnknown);
  EXPECT_EQ(g.occupiedCount(), 1u);
}

// A passage flown back through: its walls come back occupied (and inflated), its free space does
// not (unknown: A* may cross it, a scan will say); far away, the memory is dropped.
TEST(LocalGrid, OccupiedCellsThatLeftComeBackWhenTheWindowReturns) {
  LocalGridConfig cfg = smallGrid(0.1);
  cfg.memory_radius_m = 10.0;
  LocalGrid g(cfg, Eigen::Vector3d(0, 0, 0));
  const Eigen::Vector3d wall(-1.25, 0.05, 0.05), floor_free(-1.05, 0.05, 0.05);
  g.setOccupied(wall);
  g.setFree(floor_free);
  g.recenter(Eigen::Vector3d(3.0, 0, 0));
  EXPECT_EQ(g.state(wall), CellState::kOutside);
  EXPECT_EQ(g.rememberedCount(), 1u);
  EXPECT_EQ(g.occupiedCount(), 0u);
  g.recenter(Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(g.state(wall), CellState::kOccupied);
  EXPECT_TRUE(g.isInflated(g.key(Eigen::Vector3d(-1.15, 0.05, 0.05))));
  EXPECT_EQ(g.state(floor_free), CellState::kUnknown);
  EXPECT_EQ(g.rememberedCount(), 0u);  // back in the window, not twice
  EXPECT_EQ(g.occupiedCount(), 1u);
  // Leaving again and going beyond the memory radius: forgotten for good.
  g.recenter(Eigen::Vector3d(20.0, 0, 0));
  EXPECT_EQ(g.rememberedCount(), 0u);
  g.recenter(Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(g.state(wall), CellState::kUnknown);
}

// A patch of floor flown away from for 450 m comes back whole from the packed memory (cells on
// both sides of a block boundary, negative keys included), and the memory is counted.
TEST(LocalGrid, RememberedPatchComesBackAfterALongFlight) {
  LocalGridConfig cfg;
  cfg.size_x_m = cfg.size_y_m = 4.0;
  cfg.size_z_m = 2.0;
  cfg.memory_radius_m = 1000.0;
  LocalGrid g(cfg, Eigen::Vector3d(0, 0, 0));
  const size_t window_bytes = g.memoryBytes();
  std::vector<Eigen::Vector3d> patch;
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j) patch.emplace_back(0.55 - 0.1 * i, -0.45 + 0.1 * j, -0.75);
  }
  for (const Eigen::Vector3d& p : patch) g.setOccupied(p);
  for (double x = 50.0; x <= 450.0; x += 50.0) g.recenter(Eigen::Vector3d(x, 0, 0));
  EXPECT_EQ(g.rememberedCount(), 100u);
  // Four bytes per remembered cell at least.
  EXPECT_GE(g.memoryBytes(), window_bytes + 100 * 4);
  g.recenter(Eigen::Vector3d(0, 0, 0));
  for (const Eigen::Vector3d& p : patch) EXPECT_EQ(g.state(p), CellState::kOccupied);
  EXPECT_EQ(g.occupiedCount(), 100u);
  EXPECT_EQ(g.rememberedCount(), 0u);
}

// A floor seen from 4 m above it, below the 2 m tall window, is there when the vehicle comes
// down: the LiDAR does not see it again from right above it. A wall beside the window is not
// kept (it is seen again on the way there), and a hit seen twice is remembered once.
TEST(LocalGrid, AFloorSeenBelowTheWindowIsThereWhenTheWindowComesDown) {
  LocalGridConfig cfg = smallGrid(0.2);
  cfg.size_z_m = 2.0;
  cfg.memory_radius_m = 50.0;
  LocalGrid g(cfg, Eigen::Vector3d(0, 0, 0));
  std::vector<Eigen::Vector3d> floor;
  for (int i = 0; i < 10; ++i) floor.emplace_back(-0.45 + 0.1 * i, 0.55, -3.95);
  std::vector<Eigen::Vector3d> scan = floor;
  const Eigen::Vector3d beside(10.05, 0.05, 0.05);
  scan.push_back(beside);
  g.insertScan(Eigen::Vector3d(0, 0, 0.5), scan);
  g.insertScan(Eigen::Vector3d(0, 0, 0.5), scan);
  for (const Eigen::Vector3d& p : floor) EXPECT_EQ(g.state(p), CellState::kOutside);
  EXPECT_EQ(g.rememberedCount(), floor.size());
  g.recenter(Eigen::Vector3d(0, 0, -3.0));
  for (const Eigen::Vector3d& p : floor) EXPECT_EQ(g.state(p), CellState::kOccupied);
  EXPECT_TRUE(g.isInflated(g.key(Eigen::Vector3d(0.05, 0.55, -3.85))));
  EXPECT_EQ(g.rememberedCount(), 0u);
  g.recenter(Eigen::Vector3d(10.0, 0, 0));
  EXPECT_EQ(g.state(beside), CellState::kUnknown);
  // Without a memory nothing is kept.
  cfg.memory_radius_m = 0.0;
  LocalGrid forgetful(cfg, Eigen::Vector3d(0, 0, 0));
  forgetful.insertScan(Eigen::Vector3d(0, 0, 0.5), scan);
  EXPECT_EQ(forgetful.rememberedCount(), 0u);
}

/// Cells of g's window whose inflation (full, or narrow at 0.36 m) differs from that of a grid
/// built afresh around `c` from g's occupied cells; `inflated` counts g's inflated cells.
int layersDifferingFromAFreshGrid(const LocalGrid& g, const LocalGridConfig& cfg,
                                  const Eigen::Vector3d& c, int* inflated) {
  LocalGrid fresh(cfg, c);
  if (fresh.minKey() != g.minKey()) return -1;
  std::vector<Eigen::Vector3d> occ;
  g.occupiedCentersInBox(g.windowMin(), g.windowMax(), occ);
  for (const auto& p : occ) fresh.setOccupied(p);
  int differ = 0;
  *inflated = 0;
  for (const VoxelKey& k : windowKeys(g)) {
    differ += g.isInflated(k) != fresh.isInflated(k) ||
              g.isBlocked(k, true, 0.36) != fresh.isBlocked(k, true, 0.36);
    *inflated += g.isInflated(k);
  }
  return differ;
}

TEST(LocalGrid, InflationAfterRecentringMatchesAFreshGrid) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  LocalGridConfig cfg = smallGrid(0.2);
  LocalGrid g(cfg, Eigen::Vector3d(0, 0, 0));
  for (int i = 0; i < 60; ++i) g.setOccupied({u(rng), u(rng), 0.3 * u(rng)});
  for (const Eigen::Vector3d& c :
       {Eigen::Vector3d(0.7, -0.4, 0.1), Eigen::Vector3d(-0.3, 0.9, 0), Eigen::Vector3d(5, 5, 0)}) {
    g.recenter(c);
    int inflated = 0;
    EXPECT_EQ(layersDifferingFromAFreshGrid(g, cfg, c, &inflated), 0);
    if (c.x() < 1.0) {
      EXPECT_GT(inflated, 0);
    }
  }
}

// The narrow inflation layer answers exactly what the search of the cells around answers, after
// cells come and go.
TEST(LocalGrid, NarrowLayerAgreesWithTheSearchAround) {
  LocalGridConfig with = smallGrid(0.45), without = smallGrid(0.45);
  with.narrow_radius_m = 0.36;
  without.narrow_radius_m = 0.0;
  LocalGrid a(with, Eigen::Vector3d(0, 0, 0.3)), b(without, Eigen::Vector3d(0, 0, 0.3));
  a.setAllFree();
  b.setAllFree();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(-1.45, 1.45), uz(0.0, 0.6);
  std::vector<Eigen::Vector3d> placed;
  for (int i = 0; i < 60; ++i) {
    const Eigen::Vector3d p(ux(rng), ux(rng), uz(rng));
    a.setOccupied(p);
    b.setOccupied(p);
    placed.push_back(p);
  }
  for (int i = 0; i < 20; ++i) {  // some leave again
    a.setFree(placed[i]);
    b.setFree(placed[i]);
  }
  int differ = 0, narrow_free = 0, wide_blocked = 0;
  for (double x = -1.45; x < 1.5; x += 0.1)
    for (double y = -1.45; y < 1.5; y += 0.1)
      for (double z = 0.05; z < 0.6; z += 0.1) {
        const VoxelKey k = a.key({x, y, z});
        const bool na = a.isBlocked(k, true, 0.36), nb = b.isBlocked(k, true, 0.36);
        differ += na != nb;
        narrow_free += !na && a.isBlocked(k, true);
        wide_blocked += a.isBlocked(k, true);
      }
  EXPECT_EQ(differ, 0);
  EXPECT_GT(narrow_free, 0);  // the narrow search does open cells the full clearance blocks
  EXPECT_GT(wide_blocked, 0);
}

// Both inflation layers, kept incrementally while cells turn occupied and free and the window
// moves (with wrap-around of the ring buffer at negative keys), against a brute-force distance
// check of every cell to every occupied cell.
TEST(LocalGrid, InflationLayersMatchBruteForceAfterUpdatesAndMoves) {
  LocalGridConfig cfg = smallGrid(0.45);
  cfg.narrow_radius_m = 0.36;
  LocalGrid g(cfg, Eigen::Vector3d(0, 0, 0.3));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3.0, 3.0), uz(-0.2, 0.8);
  std::vector<Eigen::Vector3d> placed;
  int checked_moves = 0;
  for (const Eigen::Vector3d& c :
       {Eigen::Vector3d(0, 0, 0.3), Eigen::Vector3d(-0.8, 0.5, 0.3),
        Eigen::Vector3d(-1.7, -1.1, 0.0), Eigen::Vector3d(0.9, -2.3, 0.5),
        Eigen::Vector3d(0.2, 0.1, 0.3)}) {
    g.recenter(c);
    for (int i = 0; i < 40; ++i) {
      const Eigen::Vector3d p(c.x() + 0.5 * u(rng), c.y() + 0.5 * u(rng), uz(rng));
      g.setOccupied(p);
      placed.push_back(p);
    }
    for (int i = 0; i < 10; ++i) g.setFree(placed[(placed.size() * 7 + i * 13) % placed.size()]);
    std::vector<Eigen::Vector3d> occ;
    g.occupiedCentersInBox(g.windowMin(), g.windowMax(), occ);
    ASSERT_FALSE(occ.empty());
    int inflated = 0, narrow_open = 0;
    for (const VoxelKey& k : windowKeys(g)) {
      double d2 = std::numeric_limits<double>::infinity();
      for (const auto& o : occ) d2 = std::min(d2, (o - g.center(k)).squaredNorm());
      const bool full = d2 <= 0.45 * 0.45 + 1e-9, narrow = d2 <= 0.36 * 0.36 + 1e-9;
      ASSERT_EQ(g.isInflated(k), full) << k.x << " " << k.y << " " << k.z;
      ASSERT_EQ(g.isBlocked(k, true, 0.36), narrow) << k.x << " " << k.y << " " << k.z;
      inflated += full;
      narrow_open += full && !narrow;
    }
    EXPECT_GT(inflated, 0);
    EXPECT_GT(narrow_open, 0);
    ++checked_moves;
  }
  EXPECT_EQ(checked_moves, 5);
}

// The inflation is carried across window moves (cells leaving take their stamps off, those that
// stay stamp the slots that enter, remembered cells coming back stamp around them): after every
// move of a wandering window, in all three axes and back over remembered cells, both layers equal
// those of a grid built afresh from the same occupied cells, and once every occupied cell is
// freed no cell is inflated (a count left over would keep one).
TEST(LocalGrid, InflationCarriedAcrossMovesEqualsAFreshGrid) {
  LocalGridConfig cfg = smallGrid(0.45);
  cfg.narrow_radius_m = 0.36;
  cfg.memory_radius_m = 50.0;
  LocalGrid g(cfg, Eigen::Vector3d(0, 0, 0.3));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.4, 1.4), uz(-0.3, 0.3);
  const std::vector<Eigen::Vector3d> path = {
      {0.0, 0.0, 0.3},  {0.7, 0.2, 0.3},  {1.3, -0.6, 0.5}, {0.4, -1.2, 0.1}, {-0.8, -0.5, 0.3},
      {-1.9, 0.8, 0.6}, {-0.2, 0.4, 0.2}, {2.6, 2.1, 0.3},  {0.1, 0.0, 0.3},  {-0.3, 0.2, 0.9}};
  int compared = 0;
  for (const Eigen::Vector3d& c : path) {
    g.recenter(c);
    for (int i = 0; i < 25; ++i) g.setOccupied(c + Eigen::Vector3d(u(rng), u(rng), uz(rng)));
    int inflated = 0;
    EXPECT_EQ(layersDifferingFromAFreshGrid(g, cfg, c, &inflated), 0)
        << "after the move to " << c.transpose();
    EXPECT_GT(inflated, 0);
    ++compared;
  }
  EXPECT_EQ(compared, static_cast<int>(path.size()));
  EXPECT_GT(g.rememberedCount(), 0u);  // the path left cells behind, and came back over some
  std::vector<Eigen::Vector3d> occ;
  g.occupiedCentersInBox(g.windowMin(), g.windowMax(), occ);
  for (const auto& p : occ) g.setFree(p);
  for (const VoxelKey& k : windowKeys(g))
    ASSERT_FALSE(g.isInflated(k)) << k.x << " " << k.y << " " << k.z;
}

// Rays are cut to the window: a small window sees exactly the cells a large one sees inside it,
// from a sensor inside it and from one outside it, with rays far longer than the window.
TEST(LocalGrid, SmallWindowAgreesWithALargeOneInsideIt) {
  LocalGridConfig small = smallGrid(0.2), large = smallGrid(0.2);
  large.size_x_m = large.size_y_m = 40.0;
  large.size_z_m = 6.0;
  small.size_z_m = 2.0;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ang(-M_PI, M_PI), el(-0.4, 0.4), range(2.0, 18.0);
  for (const Eigen::Vector3d& sensor :
       {Eigen::Vector3d(0.3, -0.2, 0.5), Eigen::Vector3d(4, 3, 0.5)}) {
    LocalGrid a(small, Eigen::Vector3d(0, 0, 0.5)), b(large, Eigen::Vector3d(0, 0, 0.5));
    std::vector<Eigen::Vector3d> scan;
    for (int i = 0; i < 3000; ++i) {
      const double az = ang(rng), e = el(rng), r = range(rng);
      scan.push_back(sensor + r * Eigen::Vector3d(std::cos(e) * std::cos(az),
                                                  std::cos(e) * std::sin(az), std::sin(e)));
    }
    a.insertScan(sensor, scan);
    b.insertScan(sensor, scan);
    int observed = 0;
    for (const VoxelKey& k : windowKeys(a)) {
      ASSERT_EQ(a.state(k), b.state(k)) << k.x << " " << k.y << " " << k.z;
      observed += a.state(k) != CellState::kUnknown;
    }
    EXPECT_GT(observed, 100);
  }
}

TEST(LocalGrid, ConfigValidationNamesKey) {
  {
    LocalGridConfig c;
    c.narrow_radius_m = -0.1;
    try {
      c.validate();
      ADD_FAILURE() << "negative narrow_radius_m accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("narrow_radius_m"), std::string::npos);
    }
  }
  LocalGridConfig c;
  c.resolution_m = 0.0;
  EXPECT_THROW(c.validate(), ConfigError);
  try {
    c.validate();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("local_grid.resolution_m"), std::string::npos);
  }
}

// Reference Dijkstra on the same 26-connected graph.
double dijkstra(const LocalGrid& g, const VoxelKey& s, const VoxelKey& t) {
  std::unordered_map<VoxelKey, double, VoxelKeyHash> dist;
  using QE = std::pair<double, VoxelKey>;
  auto cmp = [](const QE& a, const QE& b) { return a.first > b.first; };
  std::priority_queue<QE, std::vector<QE>, decltype(cmp)> pq(cmp);
  dist[s] = 0;
  pq.push({0, s});
  while (!pq.empty()) {
    auto [d, k] = pq.top();
    pq.pop();
    if (d > dist[k]) continue;
    if (k == t) return d;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          if (!dx && !dy && !dz) continue;
          const VoxelKey n{k.x + dx, k.y + dy, k.z + dz};
          if (g.isBlocked(n, true)) continue;
          const double nd = d + std::sqrt(double(dx * dx + dy * dy + dz * dz));
          auto it = dist.find(n);
          if (it == dist.end() || nd < it->second) {
            dist[n] = nd;
            pq.push({nd, n});
          }
        }
  }
  return -1;
}

TEST(AStar, OptimalOnSmallRandomGrids) {
  std::mt19937 rng(42);
  int solved = 0;
  for (int trial = 0; trial < 12; ++trial) {
    LocalGrid g(smallGrid(0.0), Eigen::Vector3d(0, 0, 0.3));
    g.setAllFree();
    std::uniform_real_distribution<double> ux(-1.45, 1.45), uz(0.0, 0.6);
    for (int i = 0; i < 900; ++i) g.setOccupied({ux(rng), ux(rng), uz(rng)});
    const Eigen::Vector3d s(-1.35, -1.35, 0.25), t(1.35, 1.35, 0.35);
    g.setFree(s);
    g.setFree(t);
    AStarConfig cfg;
    cfg.shortcut = false;
    AStarPlanner astar(cfg);
    const auto r = astar.plan(g, s, t);
    const double ref = dijkstra(g, g.key(s), g.key(t));
    if (ref < 0) {
      EXPECT_EQ(r.status, AStarStatus::kNoPath);
      continue;
    }
    ASSERT_TRUE(r.ok()) << toString(r.status);
    ++solved;
    EXPECT_NEAR(r.grid_path_length_m, ref * 0.1, 1e-9) << "trial " << trial;
    EXPECT_FALSE(r.goal_adjusted);
    // The path is 26-connected through free cells.
    for (size_t i = 1; i + 1 < r.grid_path_world_m.size(); ++i)
      EXPECT_FALSE(g.isBlocked(g.key(r.grid_path_world_m[i]), true));
  }
  EXPECT_GE(solved, 6);
}

TEST(AStar, ShortcutPathKeepsLineOfSightAndEndpoints) {
  LocalGrid g(smallGrid(0.1), Eigen::Vector3d(0, 0, 0.3));
  g.setAllFree();
  for (double y = -1.0; y <= 1.45; y += 0.05)  // a wall with a gap near y = -1.3
    for (double z = -0.25; z < 0.9; z += 0.05) g.setOccupied({0.05, y, z});
  AStarPlanner astar;
  const Eigen::Vector3d s(-1.0, 1.0, 0.3), t(1.0, 1.0, 0.3);
  const auto r = astar.plan(g, s, t);
  ASSERT_TRUE(r.ok()) << toString(r.status);
  EXPECT_EQ(r.path_world_m.front(), s);
  EXPECT_EQ(r.path_world_m.back(), t);
  EXPECT_GE(r.path_world_m.size(), 3u);
  EXPECT_LT(r.path_world_m.size(), r.grid_path_world_m.size());
  for (size_t i = 0; i + 1 < r.path_world_m.size(); ++i)
    EXPECT_TRUE(astar.lineOfSight(g, r.path_world_m[i], r.path_world_m[i + 1]));
  // It has to go through the gap.
  double min_y = 1e9;
  for (const auto& p : r.path_world_m) min_y = std::min(min_y, p.y());
  EXPECT_LT(min_y, -1.0);
}

TEST(AStar, GoalInsideObstacleMovesToNearestFreeCellOrIsRefused) {
  LocalGrid g(smallGrid(0.0), Eigen::Vector3d(0, 0, 0.3));
  g.setAllFree();
  // A solid 0.3 m cube around (1, 0, 0.3).
  for (double x = 0.85; x < 1.15; x += 0.1)
    for (double y = -0.15; y < 0.15; y += 0.1)
      for (double z = 0.15; z < 0.45; z += 0.1) g.setOccupied({x, y, z});
  AStarPlanner astar;
  auto r = astar.plan(g, {-1, 0, 0.3}, {1.0, 0.0, 0.3});
  ASSERT_TRUE(r.ok()) << toString(r.status);
  EXPECT_TRUE(r.goal_adjusted);
  EXPECT_FALSE(g.isBlocked(g.key(r.path_world_m.back()), true));
  EXPECT_LT((r.path_world_m.back() - Eigen::Vector3d(1, 0, 0.3)).norm(), 0.25);

  AStarConfig strict;
  strict.goal_search_radius_m = 0.05;  // no free cell that close: refuse clearly
  r = AStarPlanner(strict).plan(g, {-1, 0, 0.3}, {1.0, 0.0, 0.3});
  EXPECT_EQ(r.status, AStarStatus::kGoalBlocked);
  EXPECT_TRUE(r.path_world_m.empty());
}

TEST(AStar, GoalOutsideWindowIsClampedOrRefused) {
  LocalGrid g(smallGrid(0.0), Eigen::Vector3d(0, 0, 0.3));
  g.setAllFree();
  AStarPlanner astar;
  auto r = astar.plan(g, {0, 0, 0.3}, {10, 0, 0.3});
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r.goal_adjusted);
  EXPECT_TRUE(g.inWindow(r.path_world_m.back()));
  EXPECT_GT(r.path_world_m.back().x(), 1.3);
  AStarConfig c;
  c.clamp_goal_to_window = false;
  r = AStarPlanner(c).plan(g, {0, 0, 0.3}, {10, 0, 0.3});
  EXPECT_EQ(r.status, AStarStatus::kGoalOutside);
  r = astar.plan(g, {10, 0, 0.3}, {0, 0, 0.3});
  EXPECT_EQ(r.status, AStarStatus::kStartOutside);
}

TEST(AStar, StartInCollisionEscapesOrStops) {
  LocalGrid g(smallGrid(0.2), Eigen::Vector3d(0, 0, 0.3));
  g.setAllFree();
  for (double y = -1.45; y < 1.5; y += 0.1)
    for (double z = -0.25; z < 0.9; z += 0.1) g.setOccupied({0.05, y, z});
  AStarPlanner astar;
  // 0.15 m from the wall: inside the 0.2 m inflation, escape to the nearest free cell.
  const Eigen::Vector3d s(-0.1, 0.0, 0.3);
  auto r = astar.plan(g, s, {-1.0, 0.5, 0.3});
  ASSERT_TRUE(r.ok()) << toString(r.status);
  EXPECT_TRUE(r.start_escaped);
  EXPECT_EQ(r.path_world_m.front(), s);
  EXPECT_FALSE(g.isBlocked(g.key(r.path_world_m[1]), true));
  EXPECT_LE((r.path_world_m[1] - s).norm(), 0.6);
  // Inside the wall with no escape allowed: stop.
  AStarConfig c;
  c.start_escape_radius_m = 0.1;
  r = AStarPlanner(c).plan(g, {0.05, 0.05, 0.35}, {-1.0, 0.5, 0.3});
  EXPECT_EQ(r.status, AStarStatus::kStartInCollision);
}

TEST(AStar, NoPathWhenGoalIsEnclosed) {
  LocalGrid g(smallGrid(0.0), Eigen::Vector3d(0, 0, 0.3));
  g.setAllFree();
  for (double y = -1.45; y < 1.5; y += 0.1)
    for (double z = -0.25; z < 0.9; z += 0.1) g.setOccupied({0.05, y, z});
  const auto r = AStarPlanner().plan(g, {-1, 0, 0.3}, {1, 0, 0.3});
  EXPECT_EQ(r.status, AStarStatus::kNoPath);
}

// smallGrid without inflation, 2 m tall (centred on z = 1 m: the floor at 0).
LocalGridConfig twoMetresTall() {
  LocalGridConfig cfg = smallGrid(0.0);
  cfg.size_z_m = 2.0;
  return cfg;
}

// Seen space in a height band with a wall across it; beyond the band nobody has looked (the
// LiDAR's blind spots straight below and above the vehicle).
LocalGrid seenBandWithAWall(double band_lo_z, double band_hi_z) {
  LocalGrid g(twoMetresTall(), Eigen::Vector3d(0, 0, 1.0));
  for (double x = -1.45; x < 1.5; x += 0.1)
    for (double y = -1.45; y < 1.5; y += 0.1)
      for (double z = band_lo_z + 0.05; z < band_hi_z; z += 0.1) {
        if (std::abs(x - 0.05) < 0.01)
          g.setOccupied({x, y, z});
        else
          g.setFree({x, y, z});
      }
  return g;
}

double minZ(const std::vector<Eigen::Vector3d>& path) {
  double z = 1e9;
  for (const auto& p : path) z = std::min(z, p.z());
  return z;
}

double maxZ(const std::vector<Eigen::Vector3d>& path) {
  double z = -1e9;
  for (const auto& p : path) z = std::max(z, p.z());
  return z;
}

// A* with unknown space free within `margin_m` of the height band (unknown_height_margin_m).
AStarResult planWithMargin(const LocalGrid& g, const Eigen::Vector3d& s, const Eigen::Vector3d& t,
                           double margin_m) {
  AStarConfig c;
  c.unknown_is_free = true;
  c.unknown_height_margin_m = margin_m;
  return AStarPlanner(c).plan(g, s, t);
}

TEST(AStar, DoesNotLeaveTheStartAndGoalHeightsThroughUnknownSpace) {
  AStarConfig c;
  c.unknown_is_free = true;
  {  // the way under the wall is a way toward an unseen floor
    const LocalGrid g = seenBandWithAWall(0.6, 2.0);
    const Eigen::Vector3d s(-1.0, 0.0, 1.35), t(1.0, 0.0, 1.35);
    EXPECT_EQ(AStarPlanner(c).plan(g, s, t).status, AStarStatus::kNoPath);
    const auto r = planWithMargin(g, s, t, 2.0);  // allowed to dive, it goes under the wall
    ASSERT_TRUE(r.ok()) << toString(r.status);
    EXPECT_LT(minZ(r.grid_path_world_m), 0.6);
  }
  {  // nor over it, toward an unseen ceiling
    const LocalGrid g = seenBandWithAWall(0.0, 1.4);
    const Eigen::Vector3d s(-1.0, 0.0, 0.65), t(1.0, 0.0, 0.65);
    EXPECT_EQ(AStarPlanner(c).plan(g, s, t).status, AStarStatus::kNoPath);
    const auto r = planWithMargin(g, s, t, 2.0);
    ASSERT_TRUE(r.ok()) << toString(r.status);
    EXPECT_GT(maxZ(r.grid_path_world_m), 1.4);
  }
  {  // unknown space from the start's height up to the goal's stays usable (optimistic
     // planning toward the unseen, up a shaft) ...
    const LocalGrid open(twoMetresTall(), Eigen::Vector3d(0, 0, 1.0));
    const Eigen::Vector3d s(-1.0, 0.0, 0.25), t(1.0, 0.0, 1.75);
    const auto r = AStarPlanner(c).plan(open, s, t);
    ASSERT_TRUE(r.ok()) << toString(r.status);
    EXPECT_GE(minZ(r.grid_path_world_m), s.z() - 0.5 - 0.05);
    EXPECT_LE(maxZ(r.grid_path_world_m), t.z() + 0.5 + 0.05);
    // ... but not down: the space below the vehicle is the LiDAR's blind cone (seen: a rock
    // beside a viewpoint 1.4 m below, unknown, hit at 2 m/s on the way down).
    const auto down = AStarPlanner(c).plan(open, t, s);
    if (down.ok()) {  // at most the goal moved up to the nearest cell it may reach
      EXPECT_GE(minZ(down.grid_path_world_m), t.z() - 0.5 - 0.05);
    }
    // Down through seen free space is fine.
    LocalGrid seen(twoMetresTall(), Eigen::Vector3d(0, 0, 1.0));
    seen.setAllFree();
    EXPECT_TRUE(AStarPlanner(c).plan(seen, t, s).ok());
  }
}

// Each replan starts where the last left the vehicle: a margin around the start would move down
// (or up) with it, half a metre per plan (seen in ed21: a door whose lower sides were unseen,
// 1.24 -> 1.03 -> 0.87 -> 0.58 m in four plans, the floor hit at 0.40 m, the goal at 1.2 m).
// Below (above) its goal, the vehicle is held to the goal's margin.
TEST(AStar, AReplanDoesNotCarryTheVehicleFurtherFromItsGoalHeightThroughUnknownSpace) {
  AStarConfig c;
  c.unknown_is_free = true;
  {  // already dipped to 0.95 m on the way to a goal at 1.35 m: not down to 0.45 m under the wall
    const LocalGrid g = seenBandWithAWall(0.6, 2.0);
    const Eigen::Vector3d s(-1.0, 0.0, 0.95), t(1.0, 0.0, 1.35);
    EXPECT_EQ(AStarPlanner(c).plan(g, s, t).status, AStarStatus::kNoPath);
    // The way under the wall is there: a margin around the start took it.
    const auto r = planWithMargin(g, s, t, 0.9);
    ASSERT_TRUE(r.ok()) << toString(r.status);
    EXPECT_LT(minZ(r.grid_path_world_m), 0.6);
  }
  {  // climbed to 1.05 m on the way to a goal at 0.65 m: not up to 1.55 m over the wall
    const LocalGrid g = seenBandWithAWall(0.0, 1.4);
    const Eigen::Vector3d s(-1.0, 0.0, 1.05), t(1.0, 0.0, 0.65);
    EXPECT_EQ(AStarPlanner(c).plan(g, s, t).status, AStarStatus::kNoPath);
  }
  {  // within the goal's margin the unknown space stays usable, around the start's own cell too
    const LocalGrid open(twoMetresTall(), Eigen::Vector3d(0, 0, 1.0));
    const Eigen::Vector3d s(-1.0, 0.0, 0.95), t(1.0, 0.0, 1.35);
    const auto r = AStarPlanner(c).plan(open, s, t);
    ASSERT_TRUE(r.ok()) << toString(r.status);
    EXPECT_FALSE(r.start_escaped);
    EXPECT_GE(minZ(r.grid_path_world_m), s.z() - 0.05 - 1e-9);
  }
}

}  // namespace
}  // namespace efs::traj
