// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "efs_common/config_check.h"
#include "observation_map_test_scenes.h"
#include "prior_guided_planner/occupancy_map.h"

namespace efs::planner {
namespace {

using testing::Box;
using testing::Scene;

const Eigen::Vector3d kOrigin(0.15, 0.15, 0.15);  // a cell centre at 0.3 m resolution

TEST(OccupancyMap, RayClearsCellsUpToTheHitAndMarksTheHit) {
  OccupancyMap m;
  const auto st = m.insertScan(kOrigin, {Eigen::Vector3d(3.15, 0.15, 0.15)});
  EXPECT_EQ(st.rays_cast, 1u);
  // Cells 0..9 along x are free, cell 10 is the hit, cell 11 was never seen.
  for (int x = 0; x < 10; ++x) EXPECT_TRUE(m.isFree({x, 0, 0})) << x;
  EXPECT_TRUE(m.isOccupied({10, 0, 0}));
  EXPECT_TRUE(m.isUnknown({11, 0, 0}));
  EXPECT_TRUE(m.isUnknown({5, 1, 0}));
  EXPECT_EQ(m.numKnownCells(), 11u);
  EXPECT_EQ(m.revision(), 1u);
}

TEST(OccupancyMap, HitWinsOverMissWithinOneScan) {
  OccupancyMap m;
  // The second ray passes through the first ray's end cell.
  m.insertScan(kOrigin, {Eigen::Vector3d(1.95, 0.15, 0.15), Eigen::Vector3d(3.15, 0.15, 0.15)});
  EXPECT_TRUE(m.isOccupied({6, 0, 0}));
  EXPECT_TRUE(m.isFree({7, 0, 0}));
  EXPECT_TRUE(m.isOccupied({10, 0, 0}));
}

TEST(OccupancyMap, RepeatedMissesClearAnOccupiedCell) {
  OccupancyMap m;
  m.insertScan(kOrigin, {Eigen::Vector3d(1.95, 0.15, 0.15)});
  ASSERT_TRUE(m.isOccupied({6, 0, 0}));
  // An occupied cell takes the weak miss: 0.85 - 0.1 * 9 < 0, so the ninth scan that sees
  // through it frees it (an obstacle that left).
  for (int i = 0; i < 8; ++i) {
    m.insertScan(kOrigin, {Eigen::Vector3d(3.15, 0.15, 0.15)});
    EXPECT_TRUE(m.isOccupied({6, 0, 0})) << i;
  }
  m.insertScan(kOrigin, {Eigen::Vector3d(3.15, 0.15, 0.15)});
  EXPECT_TRUE(m.isFree({6, 0, 0}));
  EXPECT_TRUE(m.lastScanAddedFree());
}

// A surface cell that the LiDAR hits in three scans of ten and sees through in the others (a
// surface filling part of the cell) stays occupied and stops changing the map; at the full
// miss it flips every few scans, and every flip is a change the planner's caches react to.
TEST(OccupancyMap, PartlyFilledSurfaceCellDoesNotFlicker) {
  for (const bool weak : {true, false}) {
    OccupancyConfig c;
    if (!weak) c.log_odds_miss_occupied = c.log_odds_miss;
    OccupancyMap m(c);
    int flips = 0;
    bool was_occupied = false;
    for (int scan = 0; scan < 30; ++scan) {
      const bool hit = scan % 10 == 0 || scan % 10 == 3 || scan % 10 == 6;
      m.insertScan(kOrigin, {Eigen::Vector3d(hit ? 1.95 : 3.15, 0.15, 0.15)});
      const bool occ = m.isOccupied({6, 0, 0});
      flips += scan > 0 && occ != was_occupied;
      was_occupied = occ;
    }
    if (weak) {
      EXPECT_EQ(flips, 0);
      EXPECT_TRUE(m.isOccupied({6, 0, 0}));
    } else {
      EXPECT_GT(flips, 8);
    }
  }
}

TEST(OccupancyMap, BadPointsAreCountedAndIgnored) {
  OccupancyMap m;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const auto st = m.insertScan(kOrigin, {Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d(1, inf, 0),
                                         Eigen::Vector3d(0.2, 0.15, 0.15),    // 5 cm: the vehicle
                                         Eigen::Vector3d(60.15, 0.15, 0.15),  // beyond 40 m
                                         Eigen::Vector3d(2.15, 0.15, 0.15)});
  EXPECT_EQ(st.points_in, 5u);
  EXPECT_EQ(st.points_rejected_nonfinite, 2u);
  EXPECT_EQ(st.points_rejected_too_close, 1u);
  EXPECT_EQ(st.points_clipped, 1u);
  EXPECT_EQ(st.rays_cast, 2u);
  // The clipped ray clears up to 40 m and leaves no hit.
  EXPECT_TRUE(m.isFree(m.key(Eigen::Vector3d(39.0, 0.15, 0.15))));
  EXPECT_TRUE(m.isUnknown(m.key(Eigen::Vector3d(45.0, 0.15, 0.15))));

  const uint64_t rev = m.revision();
  const auto empty = m.insertScan(kOrigin, {});
  EXPECT_EQ(empty.rays_cast, 0u);
  EXPECT_EQ(m.revision(), rev);
  const auto bad_origin = m.insertScan(Eigen::Vector3d(nan, 0, 0), {Eigen::Vector3d(1, 1, 1)});
  EXPECT_TRUE(bad_origin.rejected_scan);
  EXPECT_EQ(bad_origin.points_rejected_nonfinite, 1u);
  EXPECT_EQ(m.revision(), rev);
}

TEST(OccupancyMap, InflatedSafetyQueryAndLineOfSight) {
  Scene s;
  s.room = {Eigen::Vector3d(-5.05, -5.05, -0.05), Eigen::Vector3d(5.05, 5.05, 3.05)};
  s.solids.push_back({Eigen::Vector3d(1.95, -1.0, -0.05), Eigen::Vector3d(2.25, 1.0, 3.05)});
  OccupancyMap m;
  m.insertScan(Eigen::Vector3d(0, 0, 1.5), s.scanSphere(Eigen::Vector3d(0, 0, 1.5), 1.0));
  EXPECT_TRUE(m.isSafe(Eigen::Vector3d(0, 0, 1.5), 0.4, false));
  // The wall's face cell starts at x = 1.8: from x = 1.45 it is 0.35 m away.
  EXPECT_TRUE(m.isSafe(Eigen::Vector3d(1.45, 0, 1.5), 0.3, false));
  EXPECT_FALSE(m.isSafe(Eigen::Vector3d(1.45, 0, 1.5), 0.4, false));
  // Behind the wall nothing was seen: unknown, safe only when unknown counts as safe.
  EXPECT_FALSE(m.isSafe(Eigen::Vector3d(3.5, 0, 1.5), 0.1, false));
  EXPECT_TRUE(m.isSafe(Eigen::Vector3d(3.5, 0, 1.5), 0.1, true));
  EXPECT_TRUE(m.lineOfSight(Eigen::Vector3d(0, 0, 1.5), Eigen::Vector3d(1.5, 0.5, 1.0), true));
  EXPECT_FALSE(m.lineOfSight(Eigen::Vector3d(0, 0, 1.5), Eigen::Vector3d(3.5, 0, 1.5), false));
  EXPECT_TRUE(m.segmentSafe(Eigen::Vector3d(0, 0, 1.5), Eigen::Vector3d(0, 3, 1.5), 0.4, false));
  EXPECT_FALSE(m.segmentSafe(Eigen::Vector3d(0, 0, 1.5), Eigen::Vector3d(3.0, 0, 1.5), 0.4, true));
}

TEST(OccupancyMap, MemoryFollowsTheExploredVolumeNotTheBoundingBox) {
  // Two small rooms 1 km apart: the block count is that of two rooms, not of the span.
  OccupancyMap m;
  Scene a;
  a.room = {Eigen::Vector3d(-2, -2, -0.05), Eigen::Vector3d(2, 2, 3)};
  m.insertScan(Eigen::Vector3d(0, 0, 1.5), a.scanSphere(Eigen::Vector3d(0, 0, 1.5), 2.0));
  const size_t one = m.numBlocks();
  Scene b;
  b.room = {Eigen::Vector3d(998, -2, -0.05), Eigen::Vector3d(1002, 2, 3)};
  m.insertScan(Eigen::Vector3d(1000, 0, 1.5), b.scanSphere(Eigen::Vector3d(1000, 0, 1.5), 2.0));
  EXPECT_LE(m.numBlocks(), 2 * one + 8);
  EXPECT_LT(m.memoryBytes(), size_t(1) << 20);
}

// The cursor (whole-map passes, rays, balls) answers what state() answers, across block
// boundaries, in blocks no ray touched, and on both sides of the origin (negative block keys).
TEST(OccupancyMap, CursorAgreesWithStateEverywhere) {
  OccupancyMap m;
  Scene s;
  s.room = {Eigen::Vector3d(-4, -3, -0.05), Eigen::Vector3d(5, 3, 3)};
  m.insertScan(Eigen::Vector3d(0.5, 0.2, 1.5), s.scanSphere(Eigen::Vector3d(0.5, 0.2, 1.5), 2.0));
  int counts[3] = {0, 0, 0};
  OccupancyMap::Cursor cursor(m);
  for (int z = -6; z <= 14; ++z)
    for (int y = -14; y <= 14; ++y)
      for (int x = -18; x <= 20; ++x) {
        const VoxelKey k{x, y, z};
        const OccupancyState expected = m.state(k);
        ASSERT_EQ(cursor.state(k), expected) << x << " " << y << " " << z;
        ++counts[static_cast<int>(expected)];
      }
  // The scan saw the room: all three states were compared.
  EXPECT_GT(counts[static_cast<int>(OccupancyState::kUnknown)], 0);
  EXPECT_GT(counts[static_cast<int>(OccupancyState::kFree)], 1000);
  EXPECT_GT(counts[static_cast<int>(OccupancyState::kOccupied)], 100);
  // Block by block in the order first touched: every known cell once.
  size_t visited = 0;
  m.forEachKnownCell([&](const VoxelKey& k, double, OccupancyState st) {
    ++visited;
    EXPECT_EQ(st, m.state(k));
  });
  EXPECT_EQ(visited, m.numKnownCells());
}

TEST(OccupancyMap, ConfigErrorsNameTheKey) {
  OccupancyConfig c;
  c.resolution_m = 0.0;
  try {
    OccupancyMap m(c);
    FAIL() << "no exception";
  } catch (const efs::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("occupancy.resolution_m"), std::string::npos);
  }
  c = {};
  c.log_odds_miss = 0.3;
  EXPECT_THROW(c.validate(), efs::ConfigError);
  c = {};
  c.log_odds_miss_occupied = 0.0;
  try {
    c.validate();
    FAIL() << "no exception";
  } catch (const efs::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("occupancy.log_odds_miss_occupied"), std::string::npos);
  }
}

}  // namespace
}  // namespace efs::planner
