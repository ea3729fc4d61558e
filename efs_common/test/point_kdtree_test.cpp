// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/point_kdtree.h"

#include <gtest/gtest.h>

#include <random>

namespace efs {
namespace {

TEST(PointKdTree, KnnMatchesBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-50, 50);
  PointKdTree2d::Points pts;
  for (int i = 0; i < 500; ++i) pts.emplace_back(u(rng), u(rng));
  PointKdTree2d tree(pts);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector2d q(u(rng), u(rng));
    const auto res = tree.knn(q, 5);
    ASSERT_EQ(res.size(), 5u);
    std::vector<double> d2;
    for (const auto& p : pts) d2.push_back((p - q).squaredNorm());
    std::sort(d2.begin(), d2.end());
    for (int i = 0; i < 5; ++i) EXPECT_NEAR(res[i].second, d2[i], 1e-9);
  }
}

TEST(PointKdTree, NearestIsTheFirstOfKnn) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-20, 20);
  PointKdTree2d::Points pts;
  for (int i = 0; i < 300; ++i) pts.emplace_back(u(rng), u(rng));
  // Exact ties: a grid, as rasterised sketches give, queried at points equidistant to several.
  for (int i = 0; i < 10; ++i) pts.emplace_back(30.0 + i, 30.0);
  PointKdTree2d tree(pts);
  std::vector<Eigen::Vector2d> queries;
  for (int trial = 0; trial < 200; ++trial) queries.emplace_back(u(rng), u(rng));
  for (int i = 0; i < 9; ++i) queries.emplace_back(30.5 + i, 31.0);
  for (const Eigen::Vector2d& q : queries) {
    const auto first = tree.knn(q, 1).front();
    const auto nn = tree.nearest(q);
    EXPECT_EQ(nn.first, first.first) << q.transpose();
    EXPECT_EQ(nn.second, first.second) << q.transpose();
    double best = 1e300;
    for (const auto& p : pts) best = std::min(best, (p - q).squaredNorm());
    EXPECT_NEAR(nn.second, best, 1e-9);
  }
}

TEST(PointKdTree, RadiusSearchFindsExactlyThePointsInside) {
  PointKdTree3d::Points pts;
  for (int i = 0; i < 10; ++i) pts.emplace_back(i, 0, 0);
  PointKdTree3d tree(pts);
  const auto res = tree.radius(Eigen::Vector3d(4.5, 0, 0), 2.0);
  EXPECT_EQ(res.size(), 4u);  // 3, 4, 5, 6
  EXPECT_TRUE(tree.knn(Eigen::Vector3d::Zero(), 0).empty());
}

TEST(PointKdTree, EmptyTreeAnswersNothing) {
  PointKdTree2d tree;
  EXPECT_TRUE(tree.knn(Eigen::Vector2d::Zero(), 3).empty());
  tree.reset({});
  EXPECT_TRUE(tree.radius(Eigen::Vector2d::Zero(), 1.0).empty());
}

}  // namespace
}  // namespace efs
