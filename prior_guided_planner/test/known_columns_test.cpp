// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/known_columns.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "observation_map_test_scenes.h"

namespace efs::planner {
namespace {

using testing::Scene;

// opening_cells_test's flight through the door of a divided hall.
Scene hall() { return testing::doorHall(); }
std::vector<Eigen::Vector3d> route() { return testing::doorHallRoute(0.5); }

/// The columns a pass over the whole map finds, as (x, y) cell keys.
std::set<std::pair<int, int>> passOver(const OccupancyMap& occ) {
  std::set<std::pair<int, int>> out;
  occ.forEachKnownCell([&](const VoxelKey& k, double, OccupancyState) { out.insert({k.x, k.y}); });
  return out;
}

void expectSame(KnownColumns& known, const OccupancyMap& occ, const std::string& where) {
  const std::set<std::pair<int, int>> pass = passOver(occ);
  EXPECT_EQ(known.size(), pass.size()) << where;
  for (const auto& [x, y] : pass) ASSERT_TRUE(known.seen(x, y)) << where;
}

TEST(KnownColumns, KeepsWhatAPassOverTheWholeMapFindsScanByScan) {
  const Scene scene = hall();
  OccupancyMap occ;
  KnownColumns known(occ);
  int listed = 0, by_blocks = 0;
  for (const Eigen::Vector3d& p : route()) {
    occ.insertScan(p, scene.scanSphere(p, 2.0, 8.0));
    (occ.lastChangesListed() ? listed : by_blocks) += 1;
    known.update();
    expectSame(known, occ, "at x " + std::to_string(p.x()));
  }
  // Both kinds of changes were used, and the only whole pass was the constructor's.
  EXPECT_GT(listed, 0);
  EXPECT_GT(by_blocks, 0);
  EXPECT_EQ(known.rebuilds(), 1);
  // A column of the scanned part is seen, one far beyond the hall is not.
  const VoxelKey in = occ.key({0.0, 0.0, 1.0}), out = occ.key({40.0, 0.0, 1.0});
  EXPECT_TRUE(known.seen(in.x, in.y));
  EXPECT_FALSE(known.seen(out.x, out.y));
}

TEST(KnownColumns, AScanItDidNotSeeMakesItPassOverTheMapAgain) {
  const Scene scene = hall();
  const std::vector<Eigen::Vector3d> r = route();
  OccupancyMap occ;
  occ.insertScan(r[0], scene.scanSphere(r[0], 2.0, 8.0));
  KnownColumns known(occ);  // built on a map that already holds a scan
  expectSame(known, occ, "at construction");
  // Two scans, the first not told: its changes are lost, so the whole map is looked at again.
  occ.insertScan(r.back(), scene.scanSphere(r.back(), 2.0, 8.0));
  occ.insertScan(r[10], scene.scanSphere(r[10], 2.0, 8.0));
  known.update();
  expectSame(known, occ, "after a missed scan");
  EXPECT_EQ(known.rebuilds(), 2);
  // None told at all: asking finds it out.
  occ.insertScan(r[15], scene.scanSphere(r[15], 2.0, 8.0));
  expectSame(known, occ, "without update()");
  EXPECT_EQ(known.rebuilds(), 3);
}

}  // namespace
}  // namespace efs::planner
