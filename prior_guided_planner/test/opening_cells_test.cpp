// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/opening_cells.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "observation_map_test_scenes.h"
#include "prior_guided_planner/openings.h"

namespace efs::planner {
namespace {

using testing::Scene;

// The hall of openings_test (doorHall), flown from the left part through the door into the
// right one.
Scene hall() { return testing::doorHall(); }
std::vector<Eigen::Vector3d> route() { return testing::doorHallRoute(0.25); }

/// The hall flown along the route, scan by scan, with an index kept beside the map.
struct HallFlight {
  Scene scene = hall();
  std::vector<Eigen::Vector3d> route_world_m = route();
  OccupancyMap occ;
  OpeningCellIndex index{occ, std::nullopt};
  /// The scan from the i-th route point; update() tells the index about it.
  void scan(size_t i, bool update = true) {
    occ.insertScan(route_world_m[i], scene.scanSphere(route_world_m[i], 2.0, 8.0));
    if (update) index.update();
  }
};

void expectSame(const OpeningCells& kept, const OpeningCells& pass, const std::string& where) {
  ASSERT_EQ(kept.size(), pass.size()) << where;
  for (const auto& [k, dir] : pass) {
    const auto it = kept.find(k);
    ASSERT_NE(it, kept.end()) << where << ": cell " << k.x << " " << k.y << " " << k.z;
    EXPECT_EQ(it->second, dir) << where;
  }
}

TEST(OpeningCellIndex, KeepsWhatAPassOverTheWholeMapFindsScanByScan) {
  const Scene scene = hall();
  for (const auto& bounds : {std::optional<Eigen::AlignedBox3d>(),
                             std::optional<Eigen::AlignedBox3d>(Eigen::AlignedBox3d(
                                 Eigen::Vector3d(-4, -3, 0), Eigen::Vector3d(12, 3, 3)))}) {
    OccupancyMap occ;
    OpeningCellIndex index(occ, bounds);
    int listed = 0, by_blocks = 0, compared = 0;
    size_t most_cells = 0;
    const std::vector<Eigen::Vector3d> r = route();
    for (size_t i = 0; i < r.size(); ++i) {
      occ.insertScan(r[i], scene.scanSphere(r[i], 2.0, 8.0));
      (occ.lastChangesListed() ? listed : by_blocks) += 1;
      index.update();
      if (i % 3 != 0) continue;  // marks from several scans pile up between plans
      expectSame(index.cells(), openingCellsOf(occ, bounds), "scan " + std::to_string(i));
      most_cells = std::max(most_cells, index.cells().size());
      ++compared;
    }
    expectSame(index.cells(), openingCellsOf(occ, bounds), "the end");
    EXPECT_GT(most_cells, 100u);  // the door and the unseen part of the hall on the way
    // Both kinds of marks were used, and only the first call made a whole pass.
    EXPECT_GT(listed, 0);
    EXPECT_GT(by_blocks, 0);
    EXPECT_GT(compared, 10);
    EXPECT_EQ(index.rebuilds(), 1);
  }
}

TEST(OpeningCellIndex, AScanItDidNotSeeMakesItPassOverTheMapAgain) {
  HallFlight f;
  f.scan(0);
  f.index.cells();
  ASSERT_EQ(f.index.rebuilds(), 1);
  // Two scans, the first not told: its changes are lost, so the whole map is looked at again.
  f.scan(20, false);
  f.scan(40);
  expectSame(f.index.cells(), openingCellsOf(f.occ, std::nullopt), "after a missed scan");
  EXPECT_EQ(f.index.rebuilds(), 2);
  // And none told at all.
  f.scan(50, false);
  expectSame(f.index.cells(), openingCellsOf(f.occ, std::nullopt), "without update()");
  EXPECT_EQ(f.index.rebuilds(), 3);
}

TEST(OpeningCellIndex, OpeningsFromItsCellsAreThoseOfThePass) {
  HallFlight f;
  OpeningConfig near;
  near.search_radius_m = 6.0;
  size_t found = 0;
  for (size_t i = 0; i < f.route_world_m.size(); i += 2) {
    f.scan(i);
    const Eigen::Vector3d& robot = f.route_world_m[i];
    for (const OpeningConfig& cfg : {OpeningConfig(), near}) {
      const std::vector<Opening> kept = findOpenings(f.occ, f.index.cells(), robot, cfg);
      const std::vector<Opening> pass = findOpenings(f.occ, robot, std::nullopt, cfg);
      ASSERT_EQ(kept.size(), pass.size()) << "scan " << i;
      for (size_t j = 0; j < kept.size(); ++j) {
        EXPECT_EQ(kept[j].id, pass[j].id);
        EXPECT_EQ(kept[j].cells, pass[j].cells);
        EXPECT_EQ(kept[j].viewpoint_world_m, pass[j].viewpoint_world_m);
        EXPECT_EQ(kept[j].yaw_rad, pass[j].yaw_rad);
      }
      found += kept.size();
    }
  }
  EXPECT_GT(found, 0u);
}

}  // namespace
}  // namespace efs::planner
