// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/nearest_point_grid.h"

#include <gtest/gtest.h>

#include <random>

namespace efs {
namespace {

double bruteForce(const NearestPointGrid2d::Points& pts, const Eigen::Vector2d& q) {
  double best = 1e300;
  for (const auto& p : pts) best = std::min(best, (p - q).squaredNorm());
  return best;
}

/// Walls of a sketch-like floor plan: an outer rectangle and a few inner segments, 0.1 m apart.
NearestPointGrid2d::Points floorPlan() {
  NearestPointGrid2d::Points pts;
  const auto segment = [&](Eigen::Vector2d a, Eigen::Vector2d b) {
    const int n = static_cast<int>((b - a).norm() / 0.1);
    for (int i = 0; i <= n; ++i) pts.push_back(a + (b - a) * (static_cast<double>(i) / n));
  };
  segment({0, 0}, {40, 0});
  segment({40, 0}, {40, 25});
  segment({40, 25}, {0, 25});
  segment({0, 25}, {0, 0});
  segment({10, 0}, {10, 15});
  segment({20, 25}, {20, 8});
  segment({25, 12}, {37, 12.3});
  return pts;
}

TEST(NearestPointGrid, AnswersExactlyInsideAndOutsideTheGrid) {
  const auto pts = floorPlan();
  const NearestPointGrid2d grid(pts, {-2, -2}, {42, 27});
  ASSERT_GT(grid.numCells(), 0u);
  // Cells near the walls answer from their lists; the middle of the big room from the tree.
  EXPECT_GT(grid.numListedCells(), grid.numCells() / 2);
  EXPECT_LT(grid.numListedCells(), grid.numCells());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-10, 50);
  for (int i = 0; i < 5000; ++i) {
    const Eigen::Vector2d q(u(rng), u(rng) * 0.7);
    const auto nn = grid.nearest(q);
    EXPECT_EQ(nn.second, bruteForce(pts, q)) << q.transpose();
    EXPECT_EQ((pts[nn.first] - q).squaredNorm(), nn.second);
  }
  // Cell corners and edges, where the bound is tight.
  for (double x = -2; x <= 42; x += grid.cellSize()) {
    for (double y = -2; y <= 27; y += 3 * grid.cellSize()) {
      const Eigen::Vector2d q(x, y);
      EXPECT_EQ(grid.nearest(q).second, bruteForce(pts, q)) << q.transpose();
    }
  }
}

TEST(NearestPointGrid, RandomPointsAndAGivenCellSize) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 10);
  NearestPointGrid2d::Points pts;
  for (int i = 0; i < 200; ++i) pts.emplace_back(u(rng), u(rng));
  NearestPointGridConfig config;
  config.cell_m = 0.37;
  config.max_list = 8;
  const NearestPointGrid2d grid(pts, {0, 0}, {10, 10}, config);
  EXPECT_DOUBLE_EQ(grid.cellSize(), 0.37);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector2d q(u(rng) * 1.2 - 1.0, u(rng) * 1.2 - 1.0);
    EXPECT_EQ(grid.nearest(q).second, bruteForce(pts, q)) << q.transpose();
  }
}

TEST(NearestPointGrid, CellCountIsBounded) {
  const auto pts = floorPlan();
  NearestPointGridConfig config;
  config.max_cells = 1000;
  const NearestPointGrid2d grid(pts, {-100, -100}, {140, 125}, config);
  EXPECT_LE(grid.numCells(), 1000u);
  EXPECT_GT(grid.numCells(), 500u);
  const Eigen::Vector2d q(12.3, 4.56);
  EXPECT_EQ(grid.nearest(q).second, bruteForce(pts, q));
}

TEST(NearestPointGrid, DegenerateBoxesFallBackToTheTree) {
  const auto pts = floorPlan();
  const Eigen::Vector2d q(3.3, 7.7);
  for (const auto& [lo, hi] :
       std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>{{{0, 0}, {0, 10}},
                                                                {{5, 5}, {0, 0}},
                                                                {{0, 0}, {std::nan(""), 3}},
                                                                {{0, 0}, {1e300, 1e300}}}) {
    const NearestPointGrid2d grid(pts, lo, hi);
    EXPECT_LE(grid.numCells(), NearestPointGridConfig().max_cells);
    EXPECT_EQ(grid.nearest(q).second, bruteForce(pts, q));
  }
  const NearestPointGrid2d empty({}, {0, 0}, {1, 1});
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_EQ(empty.numCells(), 0u);
}

TEST(NearestPointGrid, DuplicatePointsKeepTheirDistance) {
  NearestPointGrid2d::Points pts(50, Eigen::Vector2d(1, 1));
  pts.emplace_back(3, 3);
  const NearestPointGrid2d grid(pts, {0, 0}, {4, 4});
  EXPECT_EQ(grid.nearest({1.5, 1}).second, 0.25);
  EXPECT_EQ(grid.nearest({3, 2.5}).first, 50u);
}

}  // namespace
}  // namespace efs
