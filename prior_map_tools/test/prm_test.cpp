// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/prm.h"

#include <gtest/gtest.h>

#include <queue>

#include "efs_common/testing/paths.h"
#include "prior_map_tools/prior_map_builder.h"
#include "test_sketches.h"

namespace efs::prior_map {
namespace {

int countRoadmapComponents(const Prm& prm) {
  const auto adj = prm.adjacency();
  std::vector<int> seen(prm.nodes_m.size(), 0);
  int comps = 0;
  for (size_t s = 0; s < seen.size(); ++s) {
    if (seen[s]) continue;
    ++comps;
    std::queue<int> q;
    q.push(static_cast<int>(s));
    seen[s] = 1;
    while (!q.empty()) {
      const int u = q.front();
      q.pop();
      for (const auto& [v, w] : adj[u]) {
        if (!seen[v]) {
          seen[v] = 1;
          q.push(v);
        }
      }
    }
  }
  return comps;
}

void expectMetric(const PriorBundle& b) {
  const DistanceMatrix& d = b.distances;
  const auto& g = b.guidepoints;
  ASSERT_EQ(d.size(), static_cast<int>(g.size()));
  for (int i = 0; i < d.size(); ++i) {
    EXPECT_EQ(d.at(i, i), 0.0);
    for (int j = 0; j < d.size(); ++j) {
      EXPECT_EQ(d.at(i, j), d.at(j, i)) << i << "," << j;
      if (!d.reachable(i, j)) {
        // Unreachable exactly when the guidepoints lie in different components.
        EXPECT_NE(g[i].component, g[j].component);
        continue;
      }
      EXPECT_GE(d.at(i, j), (g[i].position_m - g[j].position_m).norm() - 1e-9);
      for (int k = 0; k < d.size(); ++k) {
        if (d.reachable(i, k) && d.reachable(k, j)) {
          EXPECT_LE(d.at(i, j), d.at(i, k) + d.at(k, j) + 1e-9) << i << "," << j << " via " << k;
        }
      }
    }
  }
}

TEST(Prm, EdgesAreCollisionFreeAndBuildingIsOneRoadmap) {
  SketchLoadConfig lc;
  lc.scale_guess_m_per_px = 0.1;
  const LoadedSketch s = sketchFromImage(test::drawBuilding(), lc, "building");
  PriorMapConfig config;
  config.guidepoints.mapping_range_m = 3.0;
  const PriorBundle b = buildPriorBundle(s, config);
  ASSERT_GT(b.prm.nodes_m.size(), 100u);
  for (const auto& e : b.prm.edges) {
    EXPECT_TRUE(segmentTraversable(b.traversable, b.frame, b.prm.nodes_m[e.a], b.prm.nodes_m[e.b]));
    EXPECT_NEAR(e.length_m, (b.prm.nodes_m[e.a] - b.prm.nodes_m[e.b]).norm(), 1e-9);
    EXPECT_LT(e.a, e.b);
  }
  // Rooms join the corridor only through 1.2 m doors; the roadmap still reaches all of them.
  EXPECT_EQ(countRoadmapComponents(b.prm), 1);
  expectMetric(b);
}

TEST(Prm, SeparateRegionsAreUnreachableNotFar) {
  cv::Mat1b img(200, 300, uint8_t(255));
  cv::rectangle(img, cv::Rect(10, 10, 120, 120), cv::Scalar(0), 2);
  cv::rectangle(img, cv::Rect(170, 10, 100, 100), cv::Scalar(0), 2);
  SketchLoadConfig lc;
  lc.scale_guess_m_per_px = 0.1;
  PriorMapConfig config;
  config.guidepoints.mapping_range_m = 3.0;
  const PriorBundle b = buildPriorBundle(sketchFromImage(img, lc, "two"), config);
  bool saw_unreachable = false;
  for (int i = 0; i < b.distances.size(); ++i) {
    for (int j = 0; j < b.distances.size(); ++j) {
      if (b.guidepoints[i].component != b.guidepoints[j].component) {
        EXPECT_FALSE(b.distances.reachable(i, j));
        EXPECT_EQ(b.distances.at(i, j), DistanceMatrix::kUnreachable);
        saw_unreachable = true;
      }
    }
  }
  EXPECT_TRUE(saw_unreachable);
  expectMetric(b);
}

TEST(Prm, SamplingIsDeterministicPerSeed) {
  SketchLoadConfig lc;
  const LoadedSketch s = sketchFromImage(test::drawBuilding(), lc, "building");
  PriorMapConfig a, b;
  b.prm.seed = 2;
  const PriorBundle x = buildPriorBundle(s, a), y = buildPriorBundle(s, a),
                    z = buildPriorBundle(s, b);
  EXPECT_TRUE(x == y);
  EXPECT_FALSE(x.prm.nodes_m == z.prm.nodes_m);
}

TEST(Prm, Ed21DistanceMatricesAreMetric) {
  for (const char* name :
       {"sketch_ed21.png", "sketch_ed21_1.png", "sketch_ed21_2.png", "sketch_ed21_3.png"}) {
    SCOPED_TRACE(name);
    PriorMapConfig config;
    config.load.scale_guess_m_per_px = 0.12;
    config.guidepoints.mapping_range_m = 5.0;
    const PriorBundle b = buildPriorBundle(
        loadSketch(efs::testing::sharedDataPath(std::string("ed21/") + name), config.load), config);
    EXPECT_GE(b.guidepoints.size(), 20u);
    expectMetric(b);
    // Guidepoints of the main component reach each other.
    for (size_t i = 0; i < b.guidepoints.size(); ++i) {
      for (size_t j = 0; j < b.guidepoints.size(); ++j) {
        if (b.guidepoints[i].component == 1 && b.guidepoints[j].component == 1) {
          EXPECT_TRUE(b.distances.reachable(static_cast<int>(i), static_cast<int>(j)));
        }
      }
    }
  }
}

TEST(Prm, BadConfigNamesTheKey) {
  PrmConfig c;
  c.k_neighbours = 0;
  try {
    c.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("k_neighbours"), std::string::npos);
  }
}

}  // namespace
}  // namespace efs::prior_map
