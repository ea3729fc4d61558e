// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "efs_common/config_check.h"
#include "minco_traj/astar.h"
#include "minco_traj/corridor.h"
#include "minco_traj/local_grid.h"

namespace efs::traj {
namespace {

// Random pillars with a known free seed path between them.
struct Scene {
  std::vector<Eigen::Vector3d> obstacles;
  std::vector<Eigen::Vector3d> path;
};

Scene randomScene(unsigned seed, double clearance) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Scene s;
  s.path = {{0, 0, 1}, {3, 0.5, 1}, {5, 2.5, 1.3}, {8, 3, 1}};
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d p(4 + 6 * u(rng), 1.5 + 4 * u(rng), 1 + 1.5 * u(rng));
    double dmin = 1e9;
    for (size_t k = 0; k + 1 < s.path.size(); ++k) {
      const Eigen::Vector3d a = s.path[k], b = s.path[k + 1];
      const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      dmin = std::min(dmin, (a + t * (b - a) - p).norm());
    }
    if (dmin > clearance + 0.05) s.obstacles.push_back(p);
  }
  return s;
}

TEST(Corridor, ContainsSeedPathKeepsClearanceAndChainsOverlap) {
  CorridorConfig cfg;
  cfg.clearance_m = 0.3;
  CorridorBuilder builder(cfg);
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const Scene s = randomScene(seed, cfg.clearance_m);
    const auto res =
        builder.build(s.path, s.obstacles, Eigen::Vector3d(-5, -5, -2), Eigen::Vector3d(15, 15, 5));
    ASSERT_TRUE(res.ok()) << toString(res.status);
    ASSERT_GE(res.polytopes.size(), 3u);
    for (size_t k = 0; k < res.polytopes.size(); ++k) {
      const Polytope& p = res.polytopes[k];
      EXPECT_FALSE(p.clearance_reduced);
      // The whole seed segment is inside (convexity: its endpoints suffice, but sample anyway).
      for (double t = 0; t <= 1.0; t += 0.05)
        EXPECT_TRUE(p.contains(p.seed_start_m + t * (p.seed_end_m - p.seed_start_m), 1e-9));
      // No obstacle closer than the clearance to any point of the polytope: each obstacle is
      // beyond some plane by at least the clearance.
      for (const auto& o : s.obstacles) {
        const double beyond = (p.A * o - p.b).maxCoeff();
        EXPECT_GE(beyond, cfg.clearance_m - 1e-9);
      }
      // Consecutive polytopes share the path vertex between their seeds.
      if (k + 1 < res.polytopes.size()) {
        EXPECT_TRUE(p.contains(res.polytopes[k + 1].seed_start_m, 1e-9));
        EXPECT_TRUE(res.polytopes[k + 1].contains(p.seed_end_m, 1e-9));
      }
    }
  }
}

TEST(Corridor, RegionGrowsIntoFreeSpace) {
  // A single wall 1 m beside the seed: the polytope should reach close to the wall, not just hug
  // the seed.
  std::vector<Eigen::Vector3d> wall;
  for (double x = -2; x <= 4; x += 0.1)
    for (double z = -1; z <= 3; z += 0.1) wall.emplace_back(x, 1.0, z);
  CorridorConfig cfg;
  cfg.clearance_m = 0.2;
  cfg.box_margin_m = 2.0;
  const auto res = CorridorBuilder(cfg).build(
      {{0, 0, 1}, {2, 0, 1}}, wall, Eigen::Vector3d(-3, -3, -1), Eigen::Vector3d(5, 3, 3));
  ASSERT_TRUE(res.ok());
  const Polytope& p = res.polytopes[0];
  EXPECT_TRUE(p.contains({1, 0.75, 1}));
  EXPECT_FALSE(p.contains({1, 0.85, 1}));
  EXPECT_TRUE(p.contains({1, -1.5, 1}));  // the open side extends to the box margin (2 m)
}

TEST(Corridor, DegenerateInputsHaveDefinedResults) {
  CorridorBuilder builder;
  const Eigen::Vector3d lo(-5, -5, -5), hi(5, 5, 5);
  const std::vector<Eigen::Vector3d> obstacles = {{1, 0, 0}, {0, 1.5, 0}};
  // Empty path.
  EXPECT_EQ(builder.build({}, obstacles, lo, hi).status, CorridorStatus::kEmptyPath);
  // Single point and repeated points: one polytope around the point.
  auto r = builder.build({{0, 0, 0}, {0, 0, 0}}, obstacles, lo, hi);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.polytopes.size(), 1u);
  EXPECT_TRUE(r.polytopes[0].contains({0, 0, 0}));
  EXPECT_FALSE(r.polytopes[0].contains({0.8, 0, 0}));
  // No obstacles at all: the bounding box.
  r = builder.build({{0, 0, 0}, {1, 0, 0}}, {}, lo, hi);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.polytopes[0].planeCount(), 6);
  // Long segments are split so that each polytope stays local.
  r = builder.build({{-4, 0, 0}, {4, 0, 0}}, {}, lo, hi);
  EXPECT_EQ(r.polytopes.size(), 2u);
  // An obstacle on the seed itself cannot be separated: reported, not hidden.
  r = builder.build({{-1, 0, 0}, {2, 0, 0}}, obstacles, lo, hi);
  EXPECT_EQ(r.status, CorridorStatus::kSeedInCollision);
  // A seed squeezed between obstacles closer than the clearance keeps the seed inside and says
  // that its clearance was reduced.
  r = builder.build({{0, 0, 0}, {0, 0.2, 0}}, {{0.2, 0.1, 0}, {-0.2, 0.1, 0}}, lo, hi);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r.polytopes[0].clearance_reduced);
  EXPECT_TRUE(r.polytopes[0].contains({0, 0.1, 0}));
}

TEST(Corridor, MaxVolumeInscribedEllipsoidOfABox) {
  Eigen::Matrix<double, Eigen::Dynamic, 3> A(6, 3);
  Eigen::VectorXd b(6);
  A << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  b << 1, 1, 2, 2, 3, 3;
  Eigen::Matrix3d C;
  Eigen::Vector3d d;
  ASSERT_TRUE(maxVolumeInscribedEllipsoid(A, b, Eigen::Vector3d(0.5, 0.5, 0.5), 40, &C, &d));
  // The optimum is the axis-aligned ellipsoid with semi-axes 1, 2, 3 (volume factor 6).
  EXPECT_NEAR(std::abs(C.determinant()), 6.0, 0.3);
  EXPECT_LT(d.norm(), 0.1);
  EXPECT_FALSE(maxVolumeInscribedEllipsoid(A, b, Eigen::Vector3d(1, 0, 0), 40, &C, &d));
}

TEST(Corridor, FromGridAlongAStarPath) {
  LocalGridConfig gc;
  gc.size_x_m = 12;
  gc.size_y_m = 12;
  gc.size_z_m = 3;
  gc.inflation_radius_m = 0.3;
  LocalGrid grid(gc, Eigen::Vector3d(0, 0, 1));
  grid.setAllFree();
  for (double y = -6; y < 6; y += 0.1)
    for (double z = -1; z < 3; z += 0.1)
      if (std::abs(y - 1.0) > 0.6) grid.setOccupied({0.05, y, z});  // a wall with a door at y=1
  const auto astar = AStarPlanner().plan(grid, {-3, -2, 1}, {3, -2, 1});
  ASSERT_TRUE(astar.ok());
  CorridorConfig cc;
  cc.clearance_m = 0.3;
  const auto res = CorridorBuilder(cc).build(astar.path_world_m, grid);
  ASSERT_TRUE(res.ok()) << toString(res.status);
  std::vector<Eigen::Vector3d> occ;
  grid.occupiedCentersInBox(grid.windowMin(), grid.windowMax(), occ);
  for (const auto& p : res.polytopes) {
    EXPECT_TRUE(p.contains(p.seed_start_m) && p.contains(p.seed_end_m));
    for (const auto& o : occ) EXPECT_GT((p.A * o - p.b).maxCoeff(), 0.0);
  }
}

// Observed free space from z = 1.5 m up, nothing seen below (a LiDAR that does not look down).
// The polytopes stay within blind_depth_m - clearance_m of the path over the unseen part; over
// observed free space, or with the rule off, they reach down to the box.
TEST(Corridor, UnobservedSpaceFarBelowThePathIsAnObstacle) {
  LocalGridConfig gc;
  gc.size_x_m = 12;
  gc.size_y_m = 12;
  gc.size_z_m = 4;
  LocalGrid grid(gc, Eigen::Vector3d(0, 0, 2));
  for (double x = -5.95; x < 6; x += 0.1)
    for (double y = -5.95; y < 6; y += 0.1)
      for (double z = 1.55; z < 4; z += 0.1) grid.setFree({x, y, z});
  const std::vector<Eigen::Vector3d> path = {{-3, 0, 2.2}, {3, 0, 2.0}};
  CorridorConfig cc;
  cc.clearance_m = 0.3;
  cc.blind_depth_m = 0.7;
  const auto below = [](const Polytope& p, double depth_m) {
    return Eigen::Vector3d(0.5 * (p.seed_start_m + p.seed_end_m) - Eigen::Vector3d(0, 0, depth_m));
  };
  const auto blind = CorridorBuilder(cc).build(path, grid);
  ASSERT_TRUE(blind.ok()) << toString(blind.status);
  ASSERT_EQ(blind.polytopes.size(), 2u);
  for (const auto& p : blind.polytopes) {
    EXPECT_TRUE(p.contains(p.seed_start_m) && p.contains(p.seed_end_m));
    EXPECT_FALSE(p.contains(below(p, cc.blind_depth_m - cc.clearance_m + 0.15)));
    EXPECT_TRUE(p.contains(below(p, 0.2)));
  }
  cc.blind_depth_m = 0.0;
  for (const auto& p : CorridorBuilder(cc).build(path, grid).polytopes)
    EXPECT_TRUE(p.contains(below(p, 0.9)));
  cc.blind_depth_m = 0.7;
  grid.setAllFree();
  for (const auto& p : CorridorBuilder(cc).build(path, grid).polytopes)
    EXPECT_TRUE(p.contains(below(p, 0.9)));
}

TEST(Corridor, ConfigValidation) {
  CorridorConfig c;
  c.iterations = 0;
  EXPECT_THROW(c.validate(), ConfigError);
  c = CorridorConfig();
  c.blind_depth_m = c.clearance_m;  // the path itself would be blocked
  EXPECT_THROW(c.validate(), ConfigError);
  c.blind_depth_m = 0.0;
  EXPECT_NO_THROW(c.validate());
}

}  // namespace
}  // namespace efs::traj
