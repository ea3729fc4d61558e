// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/scale_icp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "efs_common/angles.h"
#include "efs_common/config_check.h"
#include "sketch_registration/sim2_fit.h"
#include "sketch_registration/synthetic_scene.h"

namespace efs::registration {
namespace {

using Eigen::Vector2d;
namespace syn = synthetic;

struct IcpScene {
  Points2d sketch;
  Points2d observed_world;
  Sim2 truth;
  Vector2d robot_world;
  std::vector<size_t> stop_ends;  ///< observed_world[0, stop_ends[k]) was seen by stop k
  Points2d stops_world;
};

IcpScene makeScene(const Sim2& truth = Sim2(0.8, 1.4, Vector2d(12.0, -5.0))) {
  IcpScene s;
  const syn::FloorPlan plan = syn::makeOfficeFloor();
  s.sketch = syn::samplePlan(plan, 0.1);
  s.truth = truth;
  const syn::FloorPlan world = syn::transformed(plan, s.truth);
  std::mt19937 rng(4);
  std::normal_distribution<double> n(0.0, 0.03);
  for (const Vector2d& p_sketch : {Vector2d(10, 18), Vector2d(25, 18), Vector2d(42, 18),
                                   Vector2d(42, 30), Vector2d(52, 25), Vector2d(42, 22)}) {
    s.robot_world = s.truth.apply(p_sketch);
    for (const auto& h : syn::castRays(world, s.robot_world, 360, 30.0)) {
      s.observed_world.push_back(h + Vector2d(n(rng), n(rng)));
    }
    s.stop_ends.push_back(s.observed_world.size());
    s.stops_world.push_back(s.robot_world);
  }
  return s;
}

/// Worst displacement of the observed walls between T and the truth.
double worstWallError(const Sim2& T, const IcpScene& s) {
  double worst = 0.0;
  for (const auto& p : s.observed_world) {
    const Vector2d c = s.truth.inverse().apply(p);
    worst = std::max(worst, (T.apply(c) - s.truth.apply(c)).norm());
  }
  return worst;
}

TEST(ScaleIcp, AFitPinnedToAScaleBoundIsInvalid) {
  const IcpScene s = makeScene();  // true scale 1.4
  PointKdTree2d::Points dense(s.observed_world.begin(), s.observed_world.end());
  const PointKdTree2d tree(dense);
  const ObservedIndex index{&tree, s.robot_world};
  ScaleIcpConfig config;
  config.scale_min = 0.5;
  config.scale_max = 1.0;  // the truth is outside: the refinement runs into the bound
  const Sim2 start(s.truth.yaw_rad, 1.0, s.truth.t_m);
  const IcpResult pinned = ScaleIcp(s.sketch, config).refine(start, s.observed_world, 0.0, &index);
  EXPECT_TRUE(pinned.scale_at_bound) << "scale " << pinned.T_world_sketch.scale;
  EXPECT_FALSE(pinned.valid);
  EXPECT_NEAR(pinned.T_world_sketch.scale, 1.0, 0.011);
  // With the truth inside the range, a fit from the truth stays there and is valid.
  config.scale_max = 2.5;
  const IcpResult free = ScaleIcp(s.sketch, config).refine(s.truth, s.observed_world, 0.0, &index);
  EXPECT_FALSE(free.scale_at_bound);
  EXPECT_TRUE(free.valid);
  EXPECT_NEAR(free.T_world_sketch.scale, s.truth.scale, 0.03);
  // The check can be switched off.
  config.scale_max = 1.0;
  config.reject_scale_at_bound = false;
  EXPECT_FALSE(
      ScaleIcp(s.sketch, config).refine(start, s.observed_world, 0.0, &index).scale_at_bound);
}

TEST(ScaleIcp, ConvergesFromPerturbedStart) {
  const IcpScene s = makeScene();
  const ScaleIcp icp(s.sketch, ScaleIcpConfig{});
  PointKdTree2d::Points dense(s.observed_world.begin(), s.observed_world.end());
  const PointKdTree2d tree(dense);
  const ObservedIndex index{&tree, s.robot_world};
  // Perturbation about the observed area's centroid: 10 deg, 2 m, 20 % scale, all at once and one
  // by one.
  Vector2d pivot = Vector2d::Zero();
  for (const auto& p : s.observed_world) pivot += p;
  pivot /= static_cast<double>(s.observed_world.size());
  auto perturb = [&](double dyaw, double dscale, const Vector2d& dt) {
    const Sim2 about(dyaw, dscale, pivot - dscale * (Eigen::Rotation2Dd(dyaw) * pivot));
    Sim2 T = about * s.truth;
    T.t_m += dt;
    return T;
  };
  // Starts inside the capture range: 10 deg + 20 % + 2 m together, and each alone.
  const std::vector<Sim2> starts = {perturb(deg2rad(10), 1.2, {2, 0}),
                                    perturb(deg2rad(10), 1.0, {0, 0}),
                                    perturb(deg2rad(-10), 1.0, {0, 0}),
                                    perturb(0, 1.2, {0, 0}),
                                    perturb(0, 0.8, {0, 0}),
                                    perturb(0, 1.0, {1.4, 1.4}),
                                    perturb(0, 1.0, {0, -2}),
                                    perturb(0, 1.0, {0, 0})};
  for (const Sim2& init : starts) {
    const IcpResult r = icp.refine(init, s.observed_world, 0.0, &index);
    EXPECT_TRUE(r.valid) << init.toString();
    EXPECT_NEAR(angleDiff(r.T_world_sketch.yaw_rad, s.truth.yaw_rad), 0.0, deg2rad(0.5));
    EXPECT_NEAR(r.T_world_sketch.scale, s.truth.scale, 0.015);
    EXPECT_LT(worstWallError(r.T_world_sketch, s), 0.6)
        << init.toString() << " -> " << r.T_world_sketch.toString();
    EXPECT_LT(r.fitness_m, 0.1);
    EXPECT_GT(r.inlierRatio(), 0.95);
  }
  // The other sign combinations are at the edge of the capture range on this floor: they must
  // either converge or be rejected (invalid or F above the default F_thresh), never be wrong and
  // accepted.
  for (const Sim2& init : {perturb(deg2rad(-10), 1.2, {0, 2}), perturb(deg2rad(10), 0.8, {-2, 0}),
                           perturb(deg2rad(-10), 0.8, {0, -2})}) {
    const IcpResult r = icp.refine(init, s.observed_world, 0.0, &index);
    if (worstWallError(r.T_world_sketch, s) > 1.0) {
      EXPECT_TRUE(!r.valid || r.fitness_m > 0.6) << init.toString();
    }
  }
}

/// Refines along the robot's stops as a live hypothesis is (each stop's walls added to the
/// earlier ones, warm-started from the last fit), from the best similarity over the first stop's
/// walls (where the triplets and their refinement put a new hypothesis).
IcpResult trackedFit(const IcpScene& s, const ScaleIcpConfig& config) {
  Points2d first_sketch, first_world;
  for (size_t i = 0; i < s.stop_ends.front(); ++i) {
    first_world.push_back(s.observed_world[i]);
    first_sketch.push_back(s.truth.inverse().apply(first_world.back()));
  }
  Sim2 T = fitSim2(first_sketch, first_world, false).T_world_sketch;
  const ScaleIcp icp(s.sketch, config);
  IcpResult r;
  for (size_t k = 0; k < s.stop_ends.size(); ++k) {
    const Points2d seen(s.observed_world.begin(), s.observed_world.begin() + s.stop_ends[k]);
    const PointKdTree2d tree(PointKdTree2d::Points(seen.begin(), seen.end()));
    const ObservedIndex index{&tree, s.stops_world[k]};
    r = icp.refine(T, seen, k == 0 ? 0.0 : 1.5, &index);
    T = r.T_world_sketch;
  }
  return r;
}

TEST(ScaleIcp, ABoundedStretchIsRefinedWhereTheDrawingsAspectIsOff) {
  // The office drawn 6 % too long along 20 deg and 6 % too narrow across it: the best similarity
  // over the first stop's walls is metres off at the far end of the 60 m floor.
  Sim2 truth(0.8, 1.4, Vector2d(12.0, -5.0));
  truth.stretch = 1.06;
  truth.stretch_axis_rad = deg2rad(20);
  const IcpScene s = makeScene(truth);
  ScaleIcpConfig config;
  config.max_stretch = 1.1;
  const IcpResult stretched = trackedFit(s, config);
  EXPECT_TRUE(stretched.valid);
  EXPECT_NEAR(stretched.T_world_sketch.stretch, 1.06, 0.005);
  EXPECT_NEAR(angleDiff(2.0 * stretched.T_world_sketch.stretch_axis_rad, deg2rad(40)), 0.0,
              deg2rad(4));
  EXPECT_LT(worstWallError(stretched.T_world_sketch, s), 0.3)
      << stretched.T_world_sketch.toString();
  EXPECT_LT(stretched.fitness_m, 0.1);
  // A similarity slides one room along.
  const IcpResult similarity = trackedFit(s, ScaleIcpConfig{});
  EXPECT_TRUE(similarity.T_world_sketch.isSimilarity());
  EXPECT_GT(worstWallError(similarity.T_world_sketch, s), 3.0);
  EXPECT_GT(similarity.fitness_m, 3.0 * stretched.fitness_m);
  // Capped below the truth, the stretch stops at the cap.
  config.max_stretch = 1.03;
  EXPECT_LE(trackedFit(s, config).T_world_sketch.stretch, 1.03 + 1e-9);
}

TEST(ScaleIcp, FitnessSeparatesRightFromWrong) {
  const IcpScene s = makeScene();
  const ScaleIcp icp(s.sketch, ScaleIcpConfig{});
  const IcpResult good = icp.evaluate(s.truth, s.observed_world);
  Sim2 wrong = s.truth;
  wrong.yaw_rad += M_PI / 2;
  const IcpResult bad = icp.evaluate(wrong, s.observed_world);
  EXPECT_LT(good.fitness_m, 0.1);
  EXPECT_TRUE(good.valid);
  EXPECT_TRUE(!bad.valid || bad.fitness_m > 3.0 * good.fitness_m);
  Sim2 shifted = s.truth;
  shifted.t_m += Vector2d(3.0, 0.0);
  const IcpResult off = icp.evaluate(shifted, s.observed_world);
  EXPECT_TRUE(!off.valid || off.fitness_m > 3.0 * good.fitness_m);
}

TEST(ScaleIcp, ForwardSlackAdmitsAPartialSketchAtTheTruthButNoWrongPlacement) {
  // The office drawn without its north-east quarter (x >= 44, y >= 20): at the true placement
  // the walls the robot saw there have no sketch wall near them, while every sketch wall it would
  // see lies on an observed one.
  const IcpScene s = makeScene();
  Points2d partial;
  for (const Vector2d& p : s.sketch) {
    if (!(p.x() >= 43.9 && p.y() >= 19.9)) partial.push_back(p);
  }
  const PointKdTree2d tree(PointKdTree2d::Points(s.observed_world.begin(), s.observed_world.end()));
  const ObservedIndex index{&tree, s.robot_world};
  ScaleIcpConfig strict;
  strict.forward_inlier_slack = 0.0;
  ScaleIcpConfig slack;
  slack.forward_inlier_slack = 0.25;
  const IcpResult truth = ScaleIcp(partial, strict).evaluate(s.truth, s.observed_world, &index);
  ASSERT_TRUE(truth.usable);
  ASSERT_TRUE(truth.reverse_inlier_ratio.has_value());
  EXPECT_GT(*truth.reverse_inlier_ratio, 0.9);
  EXPECT_LT(truth.forward_inlier_ratio, strict.min_inlier_ratio);
  EXPECT_GT(truth.forward_inlier_ratio, strict.min_inlier_ratio - slack.forward_inlier_slack);
  EXPECT_DOUBLE_EQ(truth.inlierRatio(), truth.forward_inlier_ratio);
  EXPECT_FALSE(truth.valid);
  EXPECT_TRUE(ScaleIcp(partial, slack).evaluate(s.truth, s.observed_world, &index).valid);
  // Wrong placements put sketch walls where the LiDAR saw free space: the reverse bound, which
  // the slack leaves as it is, refuses them.
  for (const Sim2& wrong : {Sim2(s.truth.yaw_rad + M_PI / 2, s.truth.scale, s.truth.t_m),
                            Sim2(s.truth.yaw_rad, s.truth.scale, s.truth.t_m + Vector2d(3, 0)),
                            Sim2(s.truth.yaw_rad, 0.8 * s.truth.scale, s.truth.t_m)}) {
    const IcpResult r = ScaleIcp(partial, slack).evaluate(wrong, s.observed_world, &index);
    EXPECT_FALSE(r.valid) << wrong.toString() << " reverse "
                          << r.reverse_inlier_ratio.value_or(-1.0) << " forward "
                          << r.forward_inlier_ratio;
  }
  // Without a reverse term the forward ratio is held to the full bound.
  EXPECT_FALSE(ScaleIcp(partial, slack).evaluate(s.truth, s.observed_world).valid);
  ScaleIcpConfig absurd;
  absurd.forward_inlier_slack = absurd.min_inlier_ratio + 0.1;
  EXPECT_THROW(absurd.validate(), ConfigError);
}

TEST(ScaleIcp, ScaleStaysWithinBounds) {
  const IcpScene s = makeScene();
  ScaleIcpConfig config;
  config.scale_min = 0.5;
  config.scale_max = 1.2;  // the truth (1.4) lies outside
  const ScaleIcp icp(s.sketch, config);
  const IcpResult r = icp.refine(s.truth, s.observed_world);
  EXPECT_LE(r.T_world_sketch.scale, 1.2 + 1e-12);
}

TEST(ScaleIcp, DegenerateInputsAreInvalidNotFatal) {
  const ScaleIcp empty_sketch(Points2d{}, ScaleIcpConfig{});
  EXPECT_FALSE(empty_sketch.refine(Sim2(), {Vector2d(1, 1)}).valid);
  const IcpScene s = makeScene();
  const ScaleIcp icp(s.sketch, ScaleIcpConfig{});
  EXPECT_FALSE(icp.refine(s.truth, {}).valid);
  Sim2 nan = s.truth;
  nan.scale = std::nan("");
  EXPECT_FALSE(icp.refine(nan, s.observed_world).valid);
  ScaleIcpConfig bad;
  bad.trim_ratio = 0.0;
  EXPECT_THROW(bad.validate(), ConfigError);
}

TEST(ScaleIcp, ReverseTermIgnoresSketchWallsFarBeyondTheObservedArea) {
  // A room 30 x 30 m drawn whole; the LiDAR has only seen the middle of the east and west walls.
  Points2d sketch, observed;
  for (double t = -15; t <= 15; t += 0.1) {
    for (const Vector2d& p : {Vector2d(15, t), Vector2d(-15, t), Vector2d(t, 15), Vector2d(t, -15)})
      sketch.push_back(p);
    if (std::abs(t) <= 5) {
      observed.emplace_back(15, t);
      observed.emplace_back(-15, t);
    }
  }
  const PointKdTree2d tree(PointKdTree2d::Points(observed.begin(), observed.end()));
  const ObservedIndex index{&tree, Vector2d::Zero()};
  ScaleIcpConfig all;
  all.reverse_extent_bins = 0;
  const IcpResult counted = ScaleIcp(sketch, all).evaluate(Sim2(), observed, &index);
  const IcpResult within = ScaleIcp(sketch, ScaleIcpConfig{}).evaluate(Sim2(), observed, &index);
  // Every visible sketch wall counts against the truth: the unseen ones are far from anything.
  EXPECT_GT(counted.reverse_fitness_m, 2.0);
  EXPECT_FALSE(counted.valid);
  // Only the walls in bearings with observations (up to reverse_extent_margin_m beyond) count.
  EXPECT_LT(within.reverse_fitness_m, 0.2);
  EXPECT_TRUE(within.valid);
}

TEST(ScaleIcp, CoverageCountsObservedWallsBeyondTheSketchAsUnexplained) {
  // Rooms of 4 m in an 8 x 8 grid. Laid at half scale from the corner, the sketch puts a wall on
  // every observed wall of the quarter it spans (walls every 2 m): the observed points it spans
  // all fit, but the three quarters it does not reach are left unexplained.
  syn::FloorPlan plan;
  for (int i = 0; i <= 8; ++i) {
    plan.push_back({Vector2d(4.0 * i, 0.0), Vector2d(4.0 * i, 32.0)});
    plan.push_back({Vector2d(0.0, 4.0 * i), Vector2d(32.0, 4.0 * i)});
  }
  const Points2d sketch = syn::samplePlan(plan, 0.1);
  const Points2d observed = syn::samplePlan(plan, 0.25);
  const ScaleIcp icp(sketch, ScaleIcpConfig{});
  const IcpResult truth = icp.evaluate(Sim2(), observed);
  const IcpResult shrunken = icp.evaluate(Sim2(0.0, 0.5, Vector2d::Zero()), observed);
  EXPECT_GT(truth.coverage, 0.99);
  EXPECT_GT(shrunken.inlierRatio(), 0.95) << shrunken.coverage;
  EXPECT_LT(shrunken.fitness_m, 0.05);
  EXPECT_TRUE(shrunken.valid);
  // The quarter plus the sketch margin (3 m): about (19 / 32)^2 of the walls.
  EXPECT_LT(shrunken.coverage, 0.45);
  EXPECT_GT(shrunken.coverage, 0.25);
}

TEST(ScaleIcp, AFitMostlyOutsideAPartialSketchIsJudgedOnWhatLiesInside) {
  // Rooms of 4 m in an 8 x 8 grid, the sketch drawn only for the 8 x 8 m corner: at the true
  // placement most observed walls lie beyond the sketch's extent. The walls inside still fit, and
  // the fit says so; valid says the observation is mostly outside (min_inside_ratio), which a
  // caller holding a reported hypothesis may accept (SketchRegistrationConfig::
  // kept_min_inside_ratio).
  syn::FloorPlan plan;
  for (int i = 0; i <= 8; ++i) {
    plan.push_back({Vector2d(4.0 * i, 0.0), Vector2d(4.0 * i, 32.0)});
    plan.push_back({Vector2d(0.0, 4.0 * i), Vector2d(32.0, 4.0 * i)});
  }
  Points2d sketch;
  for (const Vector2d& p : syn::samplePlan(plan, 0.1)) {
    if (p.x() <= 8.0 && p.y() <= 8.0) sketch.push_back(p);
  }
  const Points2d observed = syn::samplePlan(plan, 0.25);
  ScaleIcpConfig config;
  config.reverse_range_m = 0.0;
  const IcpResult r = ScaleIcp(sketch, config).evaluate(Sim2(), observed);
  EXPECT_TRUE(r.usable);
  EXPECT_FALSE(r.valid);
  // The extent is the corner plus the 3 m margin, x and y in [-3, 11]: 3 of the 9 lines each
  // way, 45 of their 129 samples.
  EXPECT_NEAR(r.inside_ratio, 3.0 / 9.0 * 45.0 / 129.0, 0.01);
  EXPECT_LT(r.inside_ratio, config.min_inside_ratio);
  // Inside, only the margin's stubs of the undrawn walls (x or y in (9, 11]) are off the sketch.
  EXPECT_GT(r.inlierRatio(), config.min_inlier_ratio);
  EXPECT_LT(r.fitness_m, 0.2);
  // Held to a lower inside bound, the same fit is valid.
  config.min_inside_ratio = 0.1;
  EXPECT_TRUE(ScaleIcp(sketch, config).evaluate(Sim2(), observed).valid);
}

}  // namespace
}  // namespace efs::registration

namespace efs::registration {
namespace {

// The clearance grid skips nearest-point searches, so it must never exceed the true distance to
// the nearest wall (anywhere, also between cells and outside the box), and it must be close
// enough to skip something: within two coarse cells' diagonal of the truth far from the walls.
TEST(SketchWalls, ClearanceIsALowerBoundOfTheDistanceToTheNearestWall) {
  // A 60 x 60 m hall, a wall point every 0.2 m, and a pillar.
  Points2d walls;
  for (double a = 0.0; a < 60.0; a += 0.2) {
    walls.emplace_back(a, 0.0);
    walls.emplace_back(a, 60.0);
    walls.emplace_back(0.0, a);
    walls.emplace_back(60.0, a);
  }
  for (double a = 0.0; a < 2.0; a += 0.2) walls.emplace_back(20.0 + a, 20.0);
  const ScaleIcp::SketchIndex index = ScaleIcp::indexSketch(walls, 5.0);
  const double cell = 2.0 * index->nearest().cellSize();
  ASSERT_LT(cell, 4.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> query(-15.0, 75.0);
  int tight = 0, far = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector2d q(query(rng), query(rng));
    double truth = std::numeric_limits<double>::infinity();
    for (const auto& w : walls) truth = std::min(truth, (w - q).norm());
    const double bound = index->clearanceAtLeast(q);
    ASSERT_GE(bound, 0.0);
    ASSERT_LE(bound, truth) << "at (" << q.x() << ", " << q.y() << ")";
    const bool inside = q.x() > -5.0 && q.x() < 65.0 && q.y() > -5.0 && q.y() < 65.0;
    if (inside && truth > 3.0 * cell) {
      ++far;
      tight += bound >= truth - 2.0 * std::sqrt(2.0) * cell;
    }
  }
  ASSERT_GT(far, 1000);
  EXPECT_EQ(tight, far);
  EXPECT_EQ(index->clearanceAtLeast({std::nan(""), 1.0}), 0.0);
  // No walls: nothing to bound, nothing skipped.
  EXPECT_EQ(ScaleIcp::indexSketch({}, 5.0)->clearanceAtLeast({1.0, 1.0}), 0.0);
}

}  // namespace
TEST(ScaleIcp, ADrawingReachJudgesTheWallsNearTheDrawingAlone) {
  // A 24 x 24 m hall drawn with its outline only; the robot saw, inside it, four 12 m walls the
  // drawing leaves out, at least 6 m from every drawn wall (passages the user forgot). Over the
  // whole view they weigh on F; within a 2 m reach of the drawing they are beyond the drawing:
  // F and the inliers come from the outline, and the coverage still counts them unexplained.
  syn::FloorPlan outline = {
      {{0, 0}, {24, 0}}, {{24, 0}, {24, 24}}, {{24, 24}, {0, 24}}, {{0, 24}, {0, 0}}};
  syn::FloorPlan seen = outline;
  for (double x : {6.0, 10.0, 14.0, 18.0}) seen.push_back({{x, 6}, {x, 18}});
  const Points2d sketch = syn::samplePlan(outline, 0.1);
  const Points2d observed = syn::samplePlan(seen, 0.25);
  ScaleIcpConfig config;
  config.reverse_range_m = 0.0;
  const ScaleIcp icp(sketch, config);
  const IcpResult whole = icp.evaluate(Sim2(), observed);
  const IcpResult near = icp.evaluate(Sim2(), observed, nullptr, 2.0);
  const double undrawn = 4 * 49.0 / static_cast<double>(observed.size());  // 12 m at 0.25 m
  EXPECT_GT(whole.fitness_m, 0.5);
  EXPECT_NEAR(whole.inside_ratio, 1.0, 1e-9);
  EXPECT_LT(near.fitness_m, 0.05);
  EXPECT_NEAR(near.inlierRatio(), 1.0, 1e-9);
  EXPECT_NEAR(near.inside_ratio, 1.0 - undrawn, 1e-9);
  EXPECT_NEAR(near.coverage, whole.coverage, 1e-9);
  EXPECT_NEAR(near.coverage, 1.0 - undrawn, 1e-9);
  // A wrong placement, 1.5 m off, is judged on the walls near the drawing too, and fails.
  const IcpResult shifted =
      icp.evaluate(Sim2(0.0, 1.0, Vector2d(1.5, 1.5)), observed, nullptr, 2.0);
  EXPECT_FALSE(config.inliersPass(shifted, config.min_inlier_ratio));
  EXPECT_GT(shifted.fitness_m, 0.6);
}

}  // namespace efs::registration
