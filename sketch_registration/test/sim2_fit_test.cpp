// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/sim2_fit.h"

#include <gtest/gtest.h>

#include <random>

#include "efs_common/angles.h"
#include "sketch_registration/dbscan.h"

namespace efs::registration {
namespace {

using Eigen::Vector2d;

TEST(Sim2Fit, TripletRecoversKnownTransformExactly) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-50, 50), yaw(-M_PI, M_PI), sc(0.3, 3.0);
  for (int trial = 0; trial < 100; ++trial) {
    const bool mirror = trial % 2 == 1;
    const Sim2 truth(yaw(rng), sc(rng), Vector2d(u(rng), u(rng)), mirror);
    Points2d c = {{u(rng), u(rng)}, {u(rng), u(rng)}, {u(rng), u(rng)}};
    Points2d p;
    for (const auto& q : c) p.push_back(truth.apply(q));
    const Sim2Fit fit = fitSim2(c, p, mirror);
    ASSERT_TRUE(fit.ok);
    EXPECT_NEAR(angleDiff(fit.T_world_sketch.yaw_rad, truth.yaw_rad), 0.0, 1e-9);
    EXPECT_NEAR(fit.T_world_sketch.scale, truth.scale, 1e-9);
    EXPECT_NEAR((fit.T_world_sketch.t_m - truth.t_m).norm(), 0.0, 1e-7);
    EXPECT_EQ(fit.T_world_sketch.reflected, mirror);
    EXPECT_NEAR(fit.rms_residual_m, 0.0, 1e-7);
    // The other handedness cannot fit a non-degenerate triangle; fitSim2Either picks the right
    // one (nearly collinear triangles fit both and are left to the preference).
    const double area =
        std::abs((c[1] - c[0]).x() * (c[2] - c[0]).y() - (c[1] - c[0]).y() * (c[2] - c[0]).x());
    const double perimeter = (c[1] - c[0]).norm() + (c[2] - c[1]).norm() + (c[0] - c[2]).norm();
    if (area / (perimeter * perimeter) > 0.03) {
      EXPECT_EQ(fitSim2Either(c, p, false).T_world_sketch.reflected, mirror);
    }
  }
}

TEST(Sim2Fit, LeastSquaresWithNoiseAndBoundedScale) {
  std::mt19937 rng(9);
  std::normal_distribution<double> n(0.0, 0.05);
  std::uniform_real_distribution<double> u(-20, 20);
  const Sim2 truth(0.4, 1.5, Vector2d(3, -2));
  Points2d c, p;
  for (int i = 0; i < 200; ++i) {
    c.emplace_back(u(rng), u(rng));
    p.push_back(truth.apply(c.back()) + Vector2d(n(rng), n(rng)));
  }
  const Sim2Fit fit = fitSim2(c, p, false);
  EXPECT_NEAR(fit.T_world_sketch.scale, 1.5, 0.01);
  EXPECT_NEAR(fit.T_world_sketch.yaw_rad, 0.4, 0.01);
  EXPECT_LT(fit.rms_residual_m, 0.1);
  const Sim2Fit bounded = fitSim2(c, p, false, 0.5, 1.2);
  EXPECT_DOUBLE_EQ(bounded.T_world_sketch.scale, 1.2);
  EXPECT_FALSE(fitSim2({Vector2d(1, 1)}, {Vector2d(2, 2)}, false).ok);
  EXPECT_FALSE(
      fitSim2({Vector2d(1, 1), Vector2d(1, 1)}, {Vector2d(0, 0), Vector2d(1, 0)}, false).ok);
}

TEST(Sim2Fit, StretchedFitRecoversAKnownStretchWithinItsBound) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-30, 30);
  for (bool mirror : {false, true}) {
    Sim2 truth(2.1, 1.9, Vector2d(40, -12), mirror);
    truth.stretch = 1.08;
    truth.stretch_axis_rad = 0.5;
    Points2d c, p;
    for (int i = 0; i < 300; ++i) {
      c.emplace_back(u(rng), u(rng));
      p.push_back(truth.apply(c.back()));
    }
    const Sim2Fit fit = fitStretchedSim2(c, p, mirror, 0.1, 10.0, 1.15);
    ASSERT_TRUE(fit.ok);
    EXPECT_NEAR((fit.T_world_sketch.matrix() - truth.matrix()).norm(), 0.0, 1e-6);
    EXPECT_LT(fit.rms_residual_m, 1e-5);
    // A similarity cannot: the same pairs leave metres.
    EXPECT_GT(fitSim2(c, p, mirror).rms_residual_m, 1.0);
    // Capped below the truth, the fit stops at the cap.
    const Sim2Fit capped = fitStretchedSim2(c, p, mirror, 0.1, 10.0, 1.04);
    ASSERT_TRUE(capped.ok);
    EXPECT_NEAR(capped.T_world_sketch.stretch, 1.04, 1e-9);
    EXPECT_LT(capped.rms_residual_m, fitSim2(c, p, mirror).rms_residual_m);
    // Without stretch allowed it is the similarity fit.
    EXPECT_TRUE(fitStretchedSim2(c, p, mirror, 0.1, 10.0, 1.0).T_world_sketch.isSimilarity());
  }
}

TEST(Sim2Fit, StretchedFitKeepsTheStartingStretchWhereItCannotBeSeen) {
  // Points on one line say nothing about the stretch across it.
  Sim2 start(0.3, 1.0, Vector2d::Zero());
  start.stretch = 1.05;
  start.stretch_axis_rad = 0.2;
  Points2d c, p;
  for (int i = 0; i < 20; ++i) {
    c.emplace_back(i, 0.0);
    p.emplace_back(2.0 * i, 1.0);
  }
  const Sim2Fit fit = fitStretchedSim2(c, p, false, 0.1, 10.0, 1.2, nullptr, &start);
  ASSERT_TRUE(fit.ok);
  EXPECT_NEAR(fit.T_world_sketch.stretch, 1.05, 1e-9);
  EXPECT_LT(fit.rms_residual_m, 1e-9);
}

TEST(Sim2Fit, TransformDistanceFollowsThePaperWeights) {
  const TransformDistanceWeights w;  // 5 / 10 / 1
  const Sim2 a(0.1, 1.0, Vector2d(0, 0)), b(0.3, 1.5, Vector2d(3, 4));
  EXPECT_NEAR(transformDistance(a, b, w), 5 * 5.0 + 10 * 0.2 + 1 * 0.5, 1e-12);
  EXPECT_NEAR(transformDistance(Sim2(3.1, 1, {0, 0}), Sim2(-3.1, 1, {0, 0}), w),
              10 * (2 * M_PI - 6.2), 1e-9);
  EXPECT_TRUE(std::isinf(transformDistance(a, Sim2(0.1, 1.0, {0, 0}, true), w)));
  // The translation-only lower bound: the larger coordinate difference, 4 of the 5 m apart.
  EXPECT_NEAR(transformDistanceLowerBound(a, b, w), 5 * 4.0, 1e-12);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (int i = 0; i < 1000; ++i) {
    const Sim2 p(u(rng), 1.0 + 0.05 * u(rng), Vector2d(u(rng), u(rng)));
    const Sim2 q(u(rng), 1.0 + 0.05 * u(rng), Vector2d(u(rng), u(rng)));
    ASSERT_LE(transformDistanceLowerBound(p, q, w), transformDistance(p, q, w));
  }
  TransformDistanceWeights negative = w;
  negative.lambda_s = -1.0;
  EXPECT_EQ(transformDistanceLowerBound(a, b, negative), 0.0);
}

TEST(FourierDescriptor, InvariantToSimilarityAndDiscriminative) {
  const Points2d tri = {{0, 0}, {10, 0}, {2, 6}};
  const Sim2 T(1.1, 2.7, Vector2d(-40, 13));
  Points2d moved;
  for (const auto& p : tri) moved.push_back(T.apply(p));
  EXPECT_NEAR(fourierDistance(fourierDescriptor(tri), fourierDescriptor(moved)), 0.0, 1e-9);
  const Points2d other = {{0, 0}, {10, 0}, {5, 0.5}};  // nearly collinear: a different shape
  EXPECT_GT(fourierDistance(fourierDescriptor(tri), fourierDescriptor(other)), 0.25);
  const Points2d quad = {{0, 0}, {8, 0}, {8, 3}, {0, 3}}, quad2 = {{0, 0}, {8, 0}, {8, 8}, {0, 8}};
  EXPECT_GT(fourierDistance(fourierDescriptor(quad), fourierDescriptor(quad2)), 0.1);
}

TEST(Dbscan, GroupsKnownClustersAndNoise) {
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 0.2);
  Points2d pts;
  const Points2d centres = {{0, 0}, {10, 0}, {0, 10}};
  for (const auto& c : centres) {
    for (int i = 0; i < 20; ++i) pts.push_back(c + Vector2d(n(rng), n(rng)));
  }
  pts.emplace_back(30, 30);  // noise
  pts.emplace_back(-30, 5);  // noise
  const auto labels =
      dbscan(pts.size(), 1.0, 3, [&](size_t i, size_t j) { return (pts[i] - pts[j]).norm(); });
  for (int k = 0; k < 3; ++k) {
    for (int i = 1; i < 20; ++i) EXPECT_EQ(labels[k * 20 + i], labels[k * 20]);
  }
  EXPECT_NE(labels[0], labels[20]);
  EXPECT_NE(labels[0], labels[40]);
  EXPECT_NE(labels[20], labels[40]);
  EXPECT_EQ(labels[60], kDbscanNoise);
  EXPECT_EQ(labels[61], kDbscanNoise);
  // With min_points 1 every point belongs to a cluster (singletons included).
  const auto all =
      dbscan(pts.size(), 1.0, 1, [&](size_t i, size_t j) { return (pts[i] - pts[j]).norm(); });
  for (int l : all) EXPECT_GE(l, 0);
}

TEST(Dbscan, ClustersTransformsWithPaperDistance) {
  const TransformDistanceWeights w;
  std::vector<Sim2> T = {Sim2(0.50, 1.0, {10, 10}), Sim2(0.52, 1.02, {10.3, 10.1}),
                         Sim2(0.49, 0.98, {9.8, 10.2}), Sim2(-2.0, 1.0, {10, 10}),
                         Sim2(-2.01, 1.0, {10.1, 10})};
  const auto labels = dbscan(T.size(), 5.0, 1,
                             [&](size_t i, size_t j) { return transformDistance(T[i], T[j], w); });
  EXPECT_EQ(labels[0], labels[1]);
  EXPECT_EQ(labels[0], labels[2]);
  EXPECT_EQ(labels[3], labels[4]);
  EXPECT_NE(labels[0], labels[3]);
}

}  // namespace
}  // namespace efs::registration
