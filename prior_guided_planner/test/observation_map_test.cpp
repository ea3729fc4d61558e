// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "efs_common/config_check.h"
#include "observation_map_test_scenes.h"
#include "prior_guided_planner/observation_map.h"

namespace efs::planner {
namespace {

TEST(ObservationMap, WellObservedRuleHandCases) {
  ObservationMapConfig c;  // 5 m, or 3 directions from within 10 m
  EXPECT_TRUE(ObservationMap::isWellObservedRule(c, 4.9, 0u));
  EXPECT_TRUE(ObservationMap::isWellObservedRule(c, 5.0, 0u));
  EXPECT_FALSE(ObservationMap::isWellObservedRule(c, 5.1, 0u));
  EXPECT_FALSE(ObservationMap::isWellObservedRule(c, 20.0, 0b11u));
  EXPECT_TRUE(ObservationMap::isWellObservedRule(c, 20.0, 0b10101u));
  c.min_view_directions = 0;  // rule (b) off
  EXPECT_FALSE(ObservationMap::isWellObservedRule(c, 20.0, 0xFFFFFFu));
}

TEST(ObservationMap, DirectionBinsSplitAzimuthAndElevation) {
  EXPECT_EQ(ObservationMap::directionBin({1, 0, 0}), 8 + 4);    // horizontal, azimuth 0
  EXPECT_EQ(ObservationMap::directionBin({0, 1, 0}), 8 + 6);    // azimuth +90 deg
  EXPECT_EQ(ObservationMap::directionBin({1, 0, 1}), 16 + 4);   // 45 deg up
  EXPECT_EQ(ObservationMap::directionBin({1, 0, -1}), 0 + 4);   // 45 deg down
  EXPECT_EQ(ObservationMap::directionBin({1, 0, 0.5}), 8 + 4);  // 26.6 deg: middle band
  EXPECT_EQ(ObservationMap::directionBin({-1, -1e-9, 0}), 8 + 0);
}

TEST(ObservationMap, CloseHitIsWellObservedFarHitIsNot) {
  ObservationMap m;
  const Eigen::Vector3d near_cell(3.15, 0.15, 0.15), far_cell(8.25, 0.15, 0.15);
  m.insertScan(Eigen::Vector3d(0.15, 0.15, 0.15), {near_cell, far_cell});
  ASSERT_NE(m.cell(m.key(near_cell)), nullptr);
  EXPECT_TRUE(m.isWellObserved(m.key(near_cell)));
  EXPECT_FALSE(m.isWellObserved(m.key(far_cell)));
  EXPECT_NEAR(m.cell(m.key(far_cell))->min_distance_m, 8.1, 1e-5);
  EXPECT_EQ(m.numSurfaceCells(), 2u);
  EXPECT_EQ(m.numWellObserved(), 1u);
  // Two isolated cells: neither borders the other, so no frontier.
  EXPECT_EQ(m.numFrontierCells(), 0u);
}

TEST(ObservationMap, ThreeDirectionsFromMidRangeMakeACellWellObserved) {
  ObservationMap m;
  const Eigen::Vector3d p(0.15, 0.15, 0.15);
  // 8 m away (beyond 5 m, within 10 m) from three azimuth sectors.
  m.insertScan(p + Eigen::Vector3d(8, 0, 0), {p});
  EXPECT_FALSE(m.isWellObserved(m.key(p)));
  m.insertScan(p + Eigen::Vector3d(8.1, 0.2, 0), {p});  // same sector: still one direction
  EXPECT_FALSE(m.isWellObserved(m.key(p)));
  m.insertScan(p + Eigen::Vector3d(0, 8, 0), {p});
  EXPECT_FALSE(m.isWellObserved(m.key(p)));
  m.insertScan(p + Eigen::Vector3d(-8, 0, 0), {p});
  EXPECT_TRUE(m.isWellObserved(m.key(p)));
  // Seen from 12 m (beyond the direction rule's range) directions do not count.
  ObservationMap far;
  for (const Eigen::Vector3d& o : {Eigen::Vector3d(12, 0, 0), Eigen::Vector3d(0, 12, 0),
                                   Eigen::Vector3d(-12, 0, 0), Eigen::Vector3d(0, -12, 0)})
    far.insertScan(p + o, {p});
  EXPECT_FALSE(far.isWellObserved(far.key(p)));
  EXPECT_EQ(far.cell(far.key(p))->hits, 4u);
}

/// Points on the plane patch p0 + u * a + v * b, u, v in [-1, 1] m, every 0.1 m.
std::vector<Eigen::Vector3d> planePatch(const Eigen::Vector3d& p0, const Eigen::Vector3d& a,
                                        const Eigen::Vector3d& b) {
  std::vector<Eigen::Vector3d> pts;
  for (double u = -1.0; u <= 1.0; u += 0.1)
    for (double v = -1.0; v <= 1.0; v += 0.1) pts.push_back(p0 + u * a + v * b);
  return pts;
}

// Rule (c): a wall seen head-on from 10 m is well observed after one scan; seen at a grazing
// angle from the same distance, from 13 m, or with the rule off, it is not.
TEST(ObservationMap, AWallSeenHeadOnFromMidRangeIsWellObserved) {
  const Eigen::Vector3d o(0.15, 0.15, 0.15);
  const Eigen::Vector3d ey = Eigen::Vector3d::UnitY(), ez = Eigen::Vector3d::UnitZ();
  const auto wellAt = [](const ObservationMap& m, const Eigen::Vector3d& p) {
    return m.isWellObserved(m.key(p));
  };
  const Eigen::Vector3d wall(10.05, 0.15, 0.15);  // wall x = 10.05, facing the sensor
  ObservationMap m;
  m.insertScan(o, planePatch(wall, ey, ez));
  EXPECT_TRUE(wellAt(m, wall));
  const std::optional<Eigen::Vector3d> n = m.surfaceNormal(m.key(wall));
  ASSERT_TRUE(n.has_value());
  EXPECT_GT(std::abs(n->x()), 0.99);

  ObservationMapConfig off;
  off.facing_max_distance_m = 0.0;
  ObservationMap m_off(off);
  m_off.insertScan(o, planePatch(wall, ey, ez));
  EXPECT_FALSE(wellAt(m_off, wall));

  ObservationMap far;
  const Eigen::Vector3d far_wall(13.05, 0.15, 0.15);
  far.insertScan(o, planePatch(far_wall, ey, ez));
  EXPECT_FALSE(wellAt(far, far_wall));

  // A wall along the line of sight (plane y = 0.45, x 9..11): the rays skim it, about 88 deg
  // from its normal.
  ObservationMap grazing;
  const Eigen::Vector3d side(10.05, 0.45, 0.15);
  grazing.insertScan(o, planePatch(side, Eigen::Vector3d::UnitX(), ez));
  EXPECT_FALSE(wellAt(grazing, side));
  ASSERT_TRUE(grazing.surfaceNormal(grazing.key(side)).has_value());

  // The floor 0.9 m below the sensor, seen from 8 m (about 6 deg above it): well observed, the
  // case the default limit is for; a 17.5 deg limit leaves it for a pass within 3 m.
  const Eigen::Vector3d floor(8.05, 0.15, -0.75);
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX();
  ObservationMap floor_map;
  floor_map.insertScan(o, planePatch(floor, ex, ey));
  EXPECT_TRUE(wellAt(floor_map, floor));
  ObservationMapConfig strict;
  strict.facing_min_cosine = testing::kStrictFacingMinCosine;
  ObservationMap floor_strict(strict);
  floor_strict.insertScan(o, planePatch(floor, ex, ey));
  EXPECT_FALSE(wellAt(floor_strict, floor));
  ASSERT_TRUE(floor_strict.surfaceNormal(floor_strict.key(floor)).has_value());
}

TEST(ObservationMap, FrontierIsPoorlyObservedNextToWellObserved) {
  ObservationMap m;
  const double r = 0.3;
  // A row of cells along x at y = 0.15; cells 0..2 seen from 2 m, cells 3..5 from 8 m.
  std::vector<Eigen::Vector3d> row;
  for (int i = 0; i < 6; ++i) row.emplace_back((i + 0.5) * r, 0.15, 0.15);
  m.insertScan(Eigen::Vector3d(0.45, 2.15, 0.15), {row[0], row[1], row[2]});
  m.takeFrontierChanges();
  m.insertScan(Eigen::Vector3d(1.35, 8.15, 0.15), {row[3], row[4], row[5]});
  EXPECT_FALSE(m.isFrontier(m.key(row[2])));  // well observed
  EXPECT_TRUE(m.isFrontier(m.key(row[3])));   // poorly observed, touches cell 2
  EXPECT_FALSE(m.isFrontier(m.key(row[4])));  // poorly observed, no well neighbour
  EXPECT_EQ(m.numFrontierCells(), 1u);
  auto changes = m.takeFrontierChanges();
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_EQ(changes[0], m.key(row[3]));
  // A close look at cell 3 moves the frontier to cell 4.
  m.insertScan(Eigen::Vector3d(1.05, 2.15, 0.15), {row[3]});
  EXPECT_FALSE(m.isFrontier(m.key(row[3])));
  EXPECT_TRUE(m.isFrontier(m.key(row[4])));
  changes = m.takeFrontierChanges();
  EXPECT_EQ(changes.size(), 2u);
  EXPECT_TRUE(m.takeFrontierChanges().empty());
  size_t all = 0, well = 0;
  m.countCellsNear(row[0], 0.65, &all, &well);
  EXPECT_EQ(all, 3u);
  EXPECT_EQ(well, 3u);
}

TEST(ObservationMap, NanPointsAndEmptyScansAreCountedAndIgnored) {
  ObservationMap m;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto st = m.insertScan(Eigen::Vector3d::Zero(),
                         {Eigen::Vector3d(nan, 1, 1), Eigen::Vector3d(1, 1, 1),
                          Eigen::Vector3d(0.1, 0, 0), Eigen::Vector3d(50, 0, 0)});
  EXPECT_EQ(st.points_in, 4u);
  EXPECT_EQ(st.points_rejected_nonfinite, 1u);
  EXPECT_EQ(st.points_rejected_range, 2u);
  EXPECT_EQ(st.points_used, 1u);
  EXPECT_EQ(m.numSurfaceCells(), 1u);
  st = m.insertScan(Eigen::Vector3d::Zero(), {});
  EXPECT_EQ(st.points_used, 0u);
  st = m.insertScan(Eigen::Vector3d(nan, 0, 0), {Eigen::Vector3d(1, 1, 1)});
  EXPECT_TRUE(st.rejected_scan);
  EXPECT_EQ(m.numSurfaceCells(), 1u);
}

TEST(ObservationMap, ConfigErrorsNameTheKey) {
  ObservationMapConfig c;
  c.well_observed_distance_m = 100.0;
  try {
    c.validate();
    FAIL() << "no exception";
  } catch (const efs::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("observation.well_observed_distance_m"),
              std::string::npos);
  }
  c = {};
  c.min_view_directions = 30;
  EXPECT_THROW(ObservationMap{c}, efs::ConfigError);
}

}  // namespace
}  // namespace efs::planner
