// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <set>
#include <tuple>

#include "efs_common/config_check.h"
#include "observation_map_test_scenes.h"
#include "prior_guided_planner/frontier_clusters.h"
#include "prior_guided_planner/observation_map.h"

namespace efs::planner {
namespace {

using testing::Scene;

// A 15.6 x 6 x 3 m room whose walls lie on cell centres (0.3 m cells), so every wall point
// falls in one layer of cells whatever the rounding.
Scene boxRoom() {
  Scene s;
  s.room = {Eigen::Vector3d(0.15, -2.85, 0.15), Eigen::Vector3d(15.75, 3.15, 3.15)};
  return s;
}

// Clusters partition the frontier cells and respect the size limits.
void expectClustersPartitionFrontier(const ObservationMap& m, const FrontierClusterer& fc) {
  std::set<std::tuple<int, int, int>> seen;
  size_t n = 0;
  for (const auto& [id, c] : fc.clusters()) {
    EXPECT_EQ(id, c.id);
    EXPECT_LE(static_cast<int>(c.cells.size()), 300);
    const Eigen::Vector3d ext = c.box_max_world_m - c.box_min_world_m;
    EXPECT_LE(ext.maxCoeff(), 4.0 + m.resolution() + 1e-9);
    for (const VoxelKey& k : c.cells) {
      EXPECT_TRUE(m.isFrontier(k));
      EXPECT_TRUE(seen.insert({k.x, k.y, k.z}).second) << "cell in two clusters";
      EXPECT_EQ(fc.clusterOf(k), id);
      ++n;
    }
  }
  EXPECT_EQ(n, m.numFrontierCells());
}

TEST(FrontierClusters, BoxRoomHasFrontiersUntilEveryWallWasSeenClosely) {
  const Scene room = boxRoom();
  ObservationMap m;
  FrontierClusterer fc;
  const Eigen::Vector3d first(2.0, 0.1, 1.6);
  m.insertScan(first, room.scanSphere(first, 1.0));
  fc.update(m);
  // The far part of the room was only seen from afar: its edge towards the closely seen part
  // is frontier, and every frontier cell lies beyond the well-observed distance.
  EXPECT_GT(m.numFrontierCells(), 50u);
  EXPECT_GT(fc.clusters().size(), 1u);
  EXPECT_LT(m.numWellObserved(), m.numSurfaceCells());
  for (const VoxelKey& k : m.frontierCells()) {
    EXPECT_GT((m.center(k) - first).norm(), 5.0 - m.resolution());
    EXPECT_GT(m.center(k).x(), first.x() + 2.0);  // towards the unseen far end, not behind
  }
  expectClustersPartitionFrontier(m, fc);

  // Flying down the room: the frontier moves ahead, then disappears.
  for (double x : {5.0, 8.0, 11.0, 14.0}) {
    const Eigen::Vector3d o(x, 0.1, 1.6);
    m.insertScan(o, room.scanSphere(o, 1.0));
    const auto st = fc.update(m);
    EXPECT_EQ(st.clusters_total, fc.clusters().size());
    expectClustersPartitionFrontier(m, fc);
  }
  EXPECT_EQ(m.numFrontierCells(), 0u);
  EXPECT_TRUE(fc.clusters().empty());
  EXPECT_EQ(m.numWellObserved(), m.numSurfaceCells());
}

TEST(FrontierClusters, UntouchedClustersKeepTheirIds) {
  // Two separate walls far apart, each with a frontier edge; a new scan at one leaves the
  // other's cluster (and so its viewpoints) alone. Poorly observed by distance alone: the
  // head-on rule would count a wall seen from 7 m in front of it as well observed.
  ObservationMapConfig oc;
  oc.facing_max_distance_m = 0.0;
  ObservationMap m(oc);
  FrontierClusterer fc;
  auto wallScan = [&](double x0, double sensor_dist) {
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 4; ++j) pts.emplace_back(x0 + (i + 0.5) * 0.3, 0.15, (j + 0.5) * 0.3);
    return std::make_pair(Eigen::Vector3d(x0 + 0.9, 0.15 + sensor_dist, 0.6), pts);
  };
  auto [o1, near1] = wallScan(0.0, 2.0);  // cells x 0..5 well observed
  auto [o2, far1] = wallScan(1.8, 7.0);   // cells x 6..11 poorly observed
  auto [o3, near2] = wallScan(30.0, 2.0);
  auto [o4, far2] = wallScan(31.8, 7.0);
  m.insertScan(o1, near1);
  m.insertScan(o2, far1);
  m.insertScan(o3, near2);
  m.insertScan(o4, far2);
  fc.update(m);
  ASSERT_EQ(fc.clusters().size(), 2u);
  const int left = fc.clusterOf(m.key(Eigen::Vector3d(1.95, 0.15, 0.15)));
  const int right = fc.clusterOf(m.key(Eigen::Vector3d(31.95, 0.15, 0.15)));
  ASSERT_GE(left, 0);
  ASSERT_GE(right, 0);
  EXPECT_EQ(fc.clusters().at(left).cells.size(), 4u);  // one column of 4 cells
  // A close look at the left wall's poorly observed part.
  auto [o5, close] = wallScan(1.8, 2.0);
  m.insertScan(o5, close);
  const auto st = fc.update(m);
  EXPECT_EQ(st.clusters_removed, 1u);
  EXPECT_EQ(fc.lastRemoved(), std::vector<int>{left});
  EXPECT_EQ(fc.clusters().count(right), 1u);
  EXPECT_EQ(fc.clusters().size(), 1u);
  expectClustersPartitionFrontier(m, fc);
}

TEST(FrontierClusters, LargeComponentsAreSplit) {
  // A 40-cell long strip of frontier (12 m) must be cut into pieces of at most 4 m.
  ObservationMap m;
  std::vector<Eigen::Vector3d> near, far;
  for (int i = 0; i < 40; ++i) {
    near.emplace_back((i + 0.5) * 0.3, 0.15, 0.15);
    far.emplace_back((i + 0.5) * 0.3, 0.45, 0.15);
  }
  for (const auto& p : near) m.insertScan(p + Eigen::Vector3d(0, -2, 0), {p});
  m.insertScan(Eigen::Vector3d(6, 9, 0.15), far);
  FrontierClusterer fc;
  fc.update(m);
  EXPECT_EQ(m.numFrontierCells(), 40u);
  EXPECT_GE(fc.clusters().size(), 3u);
  expectClustersPartitionFrontier(m, fc);
}

TEST(FrontierClusters, ConfigErrorsNameTheKey) {
  FrontierClusterConfig c;
  c.min_cluster_cells = 1000;
  EXPECT_THROW(FrontierClusterer{c}, efs::ConfigError);
  c = {};
  c.max_cluster_extent_m = -1.0;
  try {
    c.validate();
    FAIL();
  } catch (const efs::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("frontier.max_cluster_extent_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace efs::planner
