// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/greedy_prior.h"

#include <gtest/gtest.h>

#include <cmath>

#include "efs_common/config_check.h"
#include "prior_guided_planner/hierarchical_planner.h"

namespace efs::planner {
namespace {

// A straight corridor along x from -20 to 40 sketch-m, 4 m wide, sampled every metre; two
// guidepoints. Everything with x < observed_up_to_x counts as observed.
GuidepointPrior corridorPrior() {
  GuidepointPrior g;
  g.ids = {0, 1};
  g.positions_sketch_m = {Eigen::Vector2d(-10.0, 0.0), Eigen::Vector2d(30.0, 0.0)};
  g.prm_distance_m = CostMatrix(2);
  g.prm_distance_m(0, 1) = g.prm_distance_m(1, 0) = 40.0;
  for (double x = -19.5; x < 40.0; x += 1.0)
    for (double y = -1.5; y < 2.0; y += 1.0) g.predicted_free_sketch_m.emplace_back(x, y);
  g.predicted_free_cell_m = 1.0;
  return g;
}

ObservationQuery observedBelowX(double x_max) {
  return [x_max](const Eigen::Vector2d& c, double r) {
    return c.x() - r < x_max ? ObservationLevel::kWellObserved : ObservationLevel::kNone;
  };
}

PlanningInput input(const std::vector<PlanViewpoint>& vps, const GuidepointPrior& prior) {
  PlanningInput in;
  in.robot.position_world_m = Eigen::Vector3d(0.0, 0.0, 1.0);
  in.viewpoints = vps;
  in.path_length_m = [vps, r = in.robot](int a, int b) {
    const Eigen::Vector3d pa = a == kRobotNode ? r.position_world_m : vps[a].position_world_m;
    const Eigen::Vector3d pb = b == kRobotNode ? r.position_world_m : vps[b].position_world_m;
    return (pa - pb).norm();
  };
  in.prior = &prior;
  in.hypotheses = {Hypothesis{5, Sim2(), 0.9}};
  in.observation = observedBelowX(5.0);
  return in;
}

HierarchicalPlannerConfig greedyConfig() {
  HierarchicalPlannerConfig c;
  c.mode = BaselineMode::kGreedyPrior;
  return c;
}

TEST(GreedyPrior, PrefersPredictedUnknownSpaceOverANearerViewpointFacingKnownSpace) {
  const GuidepointPrior prior = corridorPrior();
  // Viewpoint 0 is 4 m behind the robot, facing the observed part (x < 5) only; viewpoint 1 is
  // 9 m ahead, facing the corridor the sketch predicts beyond what was seen.
  const std::vector<PlanViewpoint> vps = {PlanViewpoint{10, {-4.0, 0.0, 1.0}, 0.0},
                                          PlanViewpoint{11, {9.0, 0.0, 1.0}, 0.0}};
  const PlanningResult r = HierarchicalPlanner(greedyConfig()).plan(input(vps, prior));
  ASSERT_EQ(r.status, PlanningStatus::kOk);
  EXPECT_EQ(r.mode_used, BaselineMode::kGreedyPrior);
  EXPECT_EQ(r.tour.viewpoints, std::vector<int>{1});
  EXPECT_EQ(r.active_hypothesis_id, 5);
  ASSERT_EQ(r.greedy.gain_m2.size(), 2u);
  EXPECT_DOUBLE_EQ(r.greedy.gain_m2[0], 0.0);
  EXPECT_GT(r.greedy.gain_m2[1], 20.0);
  // The nearest-frontier baseline goes to the nearer one on the same input.
  HierarchicalPlannerConfig nf;
  nf.mode = BaselineMode::kNearestFrontier;
  EXPECT_EQ(HierarchicalPlanner(nf).plan(input(vps, prior)).tour.viewpoints, std::vector<int>{0});
}

TEST(GreedyPrior, EqualGainGoesToTheNearerAndGainIsDiscountedByPathLength) {
  const GuidepointPrior prior = corridorPrior();
  PlanningInput in = input(
      {PlanViewpoint{1, {30.0, 0.0, 1.0}, 0.0}, PlanViewpoint{2, {29.0, 0.0, 1.0}, 0.0}}, prior);
  in.observation = {};  // nothing observed: both see the corridor's whole width
  const PlanningResult r = HierarchicalPlanner(greedyConfig()).plan(in);
  EXPECT_EQ(r.tour.viewpoints, std::vector<int>{1});
  EXPECT_DOUBLE_EQ(r.greedy.gain_m2[0], r.greedy.gain_m2[1]);  // 10 m range inside the corridor
  EXPECT_GT(r.greedy.utility[1], r.greedy.utility[0]);
  EXPECT_NEAR(r.greedy.utility[1], r.greedy.gain_m2[1] / (29.0 + 1.0), 1e-9);
}

TEST(GreedyPrior, HypothesisPlacesAndScalesThePrediction) {
  const GuidepointPrior prior = corridorPrior();
  Hypothesis h{1, Sim2(M_PI / 2.0, 2.0, Eigen::Vector2d(100.0, 0.0)), 1.0};
  const auto pts = unobservedPredictedFree(prior, h, {}, GreedyPriorConfig{});
  ASSERT_EQ(pts.size(), prior.predicted_free_sketch_m.size());
  // Sketch (x, y) -> world (100 - 2 y, 2 x): the corridor runs along world y.
  EXPECT_TRUE(pts.front().isApprox(Eigen::Vector2d(100.0 + 3.0, -39.0)));
  // A viewpoint on the rotated corridor gains, scaled by 2^2 per sample; off it nothing.
  const std::vector<PlanViewpoint> vps = {PlanViewpoint{0, {100.0, 20.0, 1.0}, 0.0},
                                          PlanViewpoint{1, {0.0, 20.0, 1.0}, 0.0}};
  const GreedyPriorScores s = scoreGreedyPrior(vps, {20.0, 20.0}, pts, 4.0, GreedyPriorConfig{});
  EXPECT_GT(s.gain_m2[0], 0.0);
  EXPECT_DOUBLE_EQ(std::fmod(s.gain_m2[0], 4.0), 0.0);
  EXPECT_DOUBLE_EQ(s.gain_m2[1], 0.0);
  EXPECT_EQ(s.best, 0);
}

TEST(GreedyPrior, PoorlyObservedSpaceCountsAsUnknownUnlessConfigured) {
  const GuidepointPrior prior = corridorPrior();
  const ObservationQuery poor = [](const Eigen::Vector2d&, double) {
    return ObservationLevel::kPoorlyObserved;
  };
  const Hypothesis h{1, Sim2(), 1.0};
  GreedyPriorConfig c;
  EXPECT_EQ(unobservedPredictedFree(prior, h, poor, c).size(),
            prior.predicted_free_sketch_m.size());
  c.poorly_observed_is_unknown = false;
  EXPECT_TRUE(unobservedPredictedFree(prior, h, poor, c).empty());
}

TEST(GreedyPrior, UnreachableViewpointsAreNeverChosen) {
  const std::vector<PlanViewpoint> vps = {PlanViewpoint{0, {9.0, 0.0, 1.0}, 0.0},
                                          PlanViewpoint{1, {8.0, 0.0, 1.0}, 0.0}};
  const std::vector<Eigen::Vector2d> pts = {Eigen::Vector2d(9.0, 0.0)};
  const GreedyPriorScores s =
      scoreGreedyPrior(vps, {9.0, kUnreachable}, pts, 1.0, GreedyPriorConfig{});
  EXPECT_EQ(s.best, 0);
  EXPECT_DOUBLE_EQ(s.utility[1], 0.0);
  const GreedyPriorScores none =
      scoreGreedyPrior(vps, {kUnreachable, kUnreachable}, pts, 1.0, GreedyPriorConfig{});
  EXPECT_EQ(none.best, -1);
}

TEST(GreedyPrior, FallsBackToPriorFreeWithoutUsableHypothesisOrPredictedGain) {
  const GuidepointPrior prior = corridorPrior();
  const std::vector<PlanViewpoint> vps = {PlanViewpoint{10, {-4.0, 0.0, 1.0}, 0.0},
                                          PlanViewpoint{11, {9.0, 0.0, 1.0}, 0.0}};
  PlanningInput in = input(vps, prior);
  in.hypotheses = {Hypothesis{3, Sim2(0.0, std::nan(""), Eigen::Vector2d::Zero()), 1.0}};
  PlanningResult r = HierarchicalPlanner(greedyConfig()).plan(in);
  EXPECT_EQ(r.mode_used, BaselineMode::kPriorFree);
  ASSERT_EQ(r.rejected.size(), 1u);
  EXPECT_EQ(r.rejected[0].id, 3);
  EXPECT_EQ(r.tour.viewpoints.size(), 2u);
  // Everything predicted is already observed: nothing to gain, prior-free.
  in = input(vps, prior);
  in.observation = observedBelowX(1e9);
  r = HierarchicalPlanner(greedyConfig()).plan(in);
  EXPECT_EQ(r.mode_used, BaselineMode::kPriorFree);
  EXPECT_EQ(r.active_hypothesis_id, -1);
}

TEST(GreedyPrior, ConfigErrorsNameTheKey) {
  HierarchicalPlannerConfig c = greedyConfig();
  c.greedy.sensor_range_m = 0.0;
  try {
    HierarchicalPlanner p(c);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("greedy.sensor_range_m"), std::string::npos);
  }
  GuidepointPrior prior = corridorPrior();
  prior.predicted_free_sketch_m[3].y() = std::nan("");
  EXPECT_THROW(prior.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace efs::planner
