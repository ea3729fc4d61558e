// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include "minco_traj/polytope_edges.h"

namespace efs::traj {
namespace {

Polytope box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Polytope p;
  p.A.resize(6, 3);
  p.b.resize(6);
  for (int d = 0; d < 3; ++d) {
    p.A.row(2 * d) = Eigen::Vector3d::Unit(d).transpose();
    p.b(2 * d) = hi(d);
    p.A.row(2 * d + 1) = -Eigen::Vector3d::Unit(d).transpose();
    p.b(2 * d + 1) = -lo(d);
  }
  return p;
}

TEST(PolytopeSkeleton, BoxHasEightVerticesAndTwelveEdges) {
  const PolytopeSkeleton s = polytopeSkeleton(box({0, 0, 0}, {1, 2, 3}));
  ASSERT_EQ(s.vertices_m.size(), 8u);
  EXPECT_EQ(s.edges.size(), 12u);
  for (const auto& [u, v] : s.edges) {
    const double len = (s.vertices_m[u] - s.vertices_m[v]).norm();
    EXPECT_TRUE(std::abs(len - 1) < 1e-9 || std::abs(len - 2) < 1e-9 || std::abs(len - 3) < 1e-9)
        << len;
  }
}

TEST(PolytopeSkeleton, CutCornerAndRedundantPlane) {
  Polytope p = box({0, 0, 0}, {1, 1, 1});
  p.A.conservativeResize(8, 3);
  p.b.conservativeResize(8);
  p.A.row(6) = Eigen::Vector3d(1, 1, 1).normalized().transpose();  // cuts the (1,1,1) corner
  p.b(6) = 2.5 / std::sqrt(3.0);
  p.A.row(7) = Eigen::Vector3d(1, 0, 0).transpose();  // redundant: x <= 5
  p.b(7) = 5.0;
  const PolytopeSkeleton s = polytopeSkeleton(p);
  EXPECT_EQ(s.vertices_m.size(), 10u);  // 7 box corners + 3 on the cut
  EXPECT_EQ(s.edges.size(), 15u);       // 12 - 3 + 3 (cut triangle) + 3 shortened
  for (const auto& v : s.vertices_m) EXPECT_TRUE(p.contains(v, 1e-9));
}

TEST(PolytopeSkeleton, EmptyPolytopeGivesNothing) {
  Polytope p = box({0, 0, 0}, {1, 1, 1});
  p.b(0) = -1.0;  // x <= -1 and x >= 0
  EXPECT_TRUE(polytopeSkeleton(p).vertices_m.empty());
}

}  // namespace
}  // namespace efs::traj
