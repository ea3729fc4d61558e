// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <algorithm>

#include "efs_common/config_check.h"
#include "prior_guided_planner/hierarchical_planner.h"

namespace efs::planner {
namespace {

// A straight corridor sketch: guidepoints every 20 sketch-m along x, PRM = |dx|.
GuidepointPrior corridor(int n) {
  GuidepointPrior g;
  for (int i = 0; i < n; ++i) {
    g.ids.push_back(100 + i);
    g.positions_sketch_m.emplace_back(20.0 * i, 0.0);
  }
  g.prm_distance_m = CostMatrix(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) g.prm_distance_m(i, j) = 20.0 * std::abs(i - j);
  return g;
}

struct Scene {
  RobotPose robot;
  std::vector<PlanViewpoint> vps;
  PlanningInput input() const {
    PlanningInput in;
    in.robot = robot;
    in.viewpoints = vps;
    const auto v = vps;
    const auto r = robot;
    in.path_length_m = [v, r](int a, int b) {
      const Eigen::Vector3d pa = a == kRobotNode ? r.position_world_m : v[a].position_world_m;
      const Eigen::Vector3d pb = b == kRobotNode ? r.position_world_m : v[b].position_world_m;
      return (pa - pb).norm();
    };
    return in;
  }
};

// Robot at x = 20 in a corridor along x (world = sketch, scale 1). Viewpoints near guidepoints 0
// (x = 0) and 2 (x = 40), and one off to the side, attached to nothing.
Scene scene() {
  Scene s;
  s.robot.position_world_m = {20.0, 0.0, 1.0};
  s.vps = {PlanViewpoint{0, {2.0, 1.0, 1.0}, 0.0}, PlanViewpoint{1, {-1.0, -2.0, 1.0}, 0.0},
           PlanViewpoint{2, {41.0, 1.0, 1.0}, 0.0}, PlanViewpoint{3, {20.0, 60.0, 1.0}, 0.0}};
  return s;
}

TEST(HierarchicalPlanner, OneHypothesisGuidesTowardsTheCheaperEnd) {
  const GuidepointPrior prior = corridor(6);  // x = 0 .. 100: more corridor on the +x side
  PlanningInput in = scene().input();
  in.prior = &prior;
  in.hypotheses = {Hypothesis{7, Sim2(), 0.8}};
  const PlanningResult r = HierarchicalPlanner().plan(in);
  ASSERT_EQ(r.status, PlanningStatus::kOk);
  EXPECT_EQ(r.mode_used, BaselineMode::kProposed);
  EXPECT_EQ(r.active_hypothesis_id, 7);
  EXPECT_TRUE(r.selection.risk.empty());
  // Best sequence: go to x = 0 first (G0), then sweep +x: G0, G1, ... -> terminal G1 at x = 20.
  ASSERT_GE(r.selection.guidepoint_sequence.size(), 2u);
  EXPECT_EQ(r.selection.guidepoint_sequence[0], 0);
  EXPECT_EQ(r.selection.guidepoint_sequence[1], 1);
  EXPECT_TRUE(r.tour.has_terminal);
  EXPECT_NEAR(r.tour.terminal_world_m.x(), 20.0, 1e-9);
  // Target group = viewpoints of G0, plus the isolated one; the G2 viewpoint waits.
  std::vector<int> visited = r.tour.viewpoints;
  std::sort(visited.begin(), visited.end());
  EXPECT_EQ(visited, (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(r.attachments[0].states[2], GuidepointState::kExploring);
  EXPECT_EQ(r.attachments[0].states[5], GuidepointState::kUnexplored);
}

// The seen rule counts G1 (x = 20, where the robot is) explored: its free samples (x = 14 .. 26)
// all lie under well observed surface. Its viewpoint 4 at (28, 1) is then a leftover: out of
// the guided tour, unless leftover_detour_m lets the tour take it on the way.
TEST(HierarchicalPlanner, ALeftoverOnTheWayJoinsTheGuidedTour) {
  GuidepointPrior prior = corridor(6);
  prior.predicted_free_cell_m = 1.0;
  for (int k = 0; k <= 12; ++k) prior.predicted_free_sketch_m.emplace_back(14.0 + k, 0.0);
  Scene sc = scene();
  sc.vps.push_back(PlanViewpoint{4, {28.0, 1.0, 1.0}, 0.0});
  PlanningInput in = sc.input();
  in.prior = &prior;
  in.hypotheses = {Hypothesis{7, Sim2(), 0.8}};
  in.observation = [](const Eigen::Vector2d& c, double r) {
    if (r >= 5.0) return ObservationLevel::kNone;  // the paper's influence radius: nothing
    return c.x() > 13.0 && c.x() < 27.0 ? ObservationLevel::kWellObserved : ObservationLevel::kNone;
  };
  const auto plan = [&](double detour_m) {
    HierarchicalPlannerConfig cfg;
    cfg.attachment.seen_fraction = 0.9;
    cfg.leftover_detour_m = detour_m;
    return HierarchicalPlanner(cfg).plan(in);
  };
  const auto has = [](const std::vector<int>& v, int x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  const PlanningResult waits = plan(0.0);
  ASSERT_EQ(waits.mode_used, BaselineMode::kProposed);
  EXPECT_EQ(waits.attachments[0].attached_to[4], 1);
  EXPECT_EQ(waits.attachments[0].states[1], GuidepointState::kExplored);
  EXPECT_FALSE(has(waits.selection.target_viewpoints, 4));
  EXPECT_FALSE(has(waits.tour.viewpoints, 4));
  const PlanningResult taken = plan(30.0);
  ASSERT_EQ(taken.mode_used, BaselineMode::kProposed);
  EXPECT_TRUE(has(taken.selection.target_viewpoints, 4));
  EXPECT_EQ(std::count(taken.selection.target_viewpoints.begin(),
                       taken.selection.target_viewpoints.end(), 4),
            1);
  EXPECT_TRUE(has(taken.tour.viewpoints, 4));
  HierarchicalPlannerConfig bad;
  bad.leftover_detour_m = -1.0;
  EXPECT_THROW(HierarchicalPlanner{bad}, ConfigError);
}

TEST(HierarchicalPlanner, BadHypothesesAreRejectedWithReasonAndPriorFreeTakesOver) {
  const GuidepointPrior prior = corridor(4);
  PlanningInput in = scene().input();
  in.prior = &prior;
  Hypothesis nan_scale{1, Sim2(0.0, std::nan(""), {0, 0}), 0.9};
  Hypothesis zero_scale{2, Sim2(0.0, 0.0, {0, 0}), 0.9};
  Hypothesis negative_scale{3, Sim2(0.0, -1.0, {0, 0}), 0.9};
  in.hypotheses = {nan_scale, zero_scale, negative_scale};
  const PlanningResult r = HierarchicalPlanner().plan(in);
  ASSERT_EQ(r.rejected.size(), 3u);
  EXPECT_EQ(r.rejected[0].id, 1);
  EXPECT_NE(r.rejected[0].reason.find("not finite"), std::string::npos);
  EXPECT_NE(r.rejected[1].reason.find("not positive"), std::string::npos);
  EXPECT_NE(r.rejected[2].reason.find("not positive"), std::string::npos);
  EXPECT_EQ(r.mode_used, BaselineMode::kPriorFree);
  EXPECT_EQ(r.tour.viewpoints.size(), 4u);
  EXPECT_EQ(r.active_hypothesis_id, -1);
}

TEST(HierarchicalPlanner, TwoHypothesesUseTheRiskStep) {
  const GuidepointPrior prior = corridor(6);
  PlanningInput in = scene().input();
  in.prior = &prior;
  // The second hypothesis is mirrored along x (yaw pi, shifted): its corridor runs to -x.
  in.hypotheses = {Hypothesis{1, Sim2(), 0.7}, Hypothesis{2, Sim2(M_PI, 1.0, {40.0, 0.0}), 0.3}};
  const PlanningResult r = HierarchicalPlanner().plan(in);
  EXPECT_EQ(r.mode_used, BaselineMode::kProposed);
  ASSERT_EQ(r.sequences.size(), 2u);
  EXPECT_EQ(r.selection.risk.size(), r.groups.size());
  ASSERT_GE(r.selection.group, 0);
  // The selected group has the minimum risk.
  for (double risk : r.selection.risk) EXPECT_GE(risk, r.selection.risk[r.selection.group] - 1e-9);
  EXPECT_FALSE(r.tour.viewpoints.empty());
}

TEST(HierarchicalPlanner, KeptRolloutWorkersChangeNothing) {
  const GuidepointPrior prior = corridor(24);  // more guidepoints than dynamic programming takes
  PlanningInput in = scene().input();
  in.prior = &prior;
  in.hypotheses = {Hypothesis{1, Sim2(), 0.6}, Hypothesis{2, Sim2(0.05, 1.02, {3.0, 1.0}), 0.4}};
  const PlanningResult fresh = HierarchicalPlanner().plan(in);
  ASSERT_EQ(fresh.sequences.size(), 2u);
  EXPECT_GT(fresh.sequences[0].problem.problem.cost.size(), 14);  // the root rollout is an ILS
  HierarchicalPlannerConfig cfg;
  cfg.mcts.threads = 2;
  cfg.reuse_sequences = false;  // solved again each time, by the kept workers
  HierarchicalPlanner kept(cfg);
  for (int run = 0; run < 2; ++run) {
    const PlanningResult r = kept.plan(in);
    ASSERT_EQ(r.sequences.size(), fresh.sequences.size());
    for (size_t k = 0; k < r.sequences.size(); ++k) {
      EXPECT_EQ(r.sequences[k].mcts.sequence, fresh.sequences[k].mcts.sequence);
      EXPECT_EQ(r.sequences[k].mcts.best_length_by_first,
                fresh.sequences[k].mcts.best_length_by_first);
    }
    EXPECT_EQ(r.selection.guidepoint_sequence, fresh.selection.guidepoint_sequence);
    EXPECT_EQ(r.tour.viewpoints, fresh.tour.viewpoints);
  }
  // Each hypothesis has its own seed, as a sequencer configured with it would.
  MctsConfig second = cfg.mcts;
  second.seed = cfg.mcts.seed + 7919;
  EXPECT_EQ(MctsSequencer(second).solve(fresh.sequences[1].problem.problem).sequence,
            fresh.sequences[1].mcts.sequence);
}

TEST(HierarchicalPlanner, GuidepointsFarOutsideTheMapAreIgnored) {
  const GuidepointPrior prior = corridor(4);
  PlanningInput in = scene().input();
  in.prior = &prior;
  in.bounds_world_m = Eigen::AlignedBox2d(Eigen::Vector2d(-10, -10), Eigen::Vector2d(70, 70));
  // Shifted 10 km away: every guidepoint is outside; no target group -> prior-free.
  in.hypotheses = {Hypothesis{1, Sim2(0.0, 1.0, {10000.0, 0.0}), 1.0}};
  const PlanningResult r = HierarchicalPlanner().plan(in);
  for (auto s : r.attachments[0].states) EXPECT_EQ(s, GuidepointState::kOutside);
  EXPECT_EQ(r.mode_used, BaselineMode::kPriorFree);
  EXPECT_EQ(r.tour.viewpoints.size(), 4u);
}

TEST(HierarchicalPlanner, NoViewpointsAndUnreachableViewpoints) {
  const GuidepointPrior prior = corridor(4);
  PlanningInput in = scene().input();
  in.prior = &prior;
  in.viewpoints.clear();
  EXPECT_EQ(HierarchicalPlanner().plan(in).status, PlanningStatus::kNoViewpoints);
  in = scene().input();
  in.path_length_m = [](int, int) { return kUnreachable; };
  const PlanningResult r = HierarchicalPlanner().plan(in);
  EXPECT_EQ(r.status, PlanningStatus::kNoReachableViewpoint);
  EXPECT_EQ(r.tour.unreachable_viewpoints.size(), 4u);
  EXPECT_TRUE(r.tour.viewpoints.empty());
  in = scene().input();
  in.path_length_m = nullptr;
  EXPECT_THROW(HierarchicalPlanner().plan(in), std::invalid_argument);
}

TEST(HierarchicalPlanner, NoPriorMeansPriorFreeAndModesAreSelectable) {
  PlanningInput in = scene().input();
  PlanningResult r = HierarchicalPlanner().plan(in);
  EXPECT_EQ(r.mode_used, BaselineMode::kPriorFree);
  EXPECT_EQ(r.tour.viewpoints.size(), 4u);
  HierarchicalPlannerConfig cfg;
  cfg.mode = BaselineMode::kNearestFrontier;
  r = HierarchicalPlanner(cfg).plan(in);
  EXPECT_EQ(r.tour.viewpoints, std::vector<int>{0});  // 18 m away, the nearest
  EXPECT_EQ(parseBaselineMode("prior_free"), BaselineMode::kPriorFree);
  EXPECT_EQ(toString(BaselineMode::kGreedyPrior), "greedy_prior");
  try {
    parseBaselineMode("epic", "planner.mode");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("planner.mode"), std::string::npos);
  }
  cfg.mode = BaselineMode::kGreedyPrior;  // no prior here: prior-free
  r = HierarchicalPlanner(cfg).plan(in);
  EXPECT_EQ(r.mode_used, BaselineMode::kPriorFree);
  EXPECT_EQ(r.tour.viewpoints.size(), 4u);
  cfg = HierarchicalPlannerConfig();
  cfg.attachment.rho_m = -1.0;
  try {
    HierarchicalPlanner p(cfg);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("attachment.rho_m"), std::string::npos);
  }
  // Paper defaults.
  cfg = HierarchicalPlannerConfig();
  EXPECT_DOUBLE_EQ(cfg.mcts.exploration_constant, 1.414);
  EXPECT_DOUBLE_EQ(cfg.attachment.rho_m, 20.0);
  EXPECT_DOUBLE_EQ(cfg.fe_tsp.v_max_mps, 4.0);
}

// Path lengths of the prior-free tour are searched among the nearest viewpoints only; the tour
// covers up to prior_free_max_viewpoints of them; unreachable ones are reported, not toured.
TEST(HierarchicalPlanner, PriorFreeTourSearchesLengthsAmongTheNearestViewpointsOnly) {
  PlanningInput in;
  in.robot.position_world_m = Eigen::Vector3d(0, 0, 1);
  for (int i = 0; i < 30; ++i)
    in.viewpoints.push_back(PlanViewpoint{i, {3.0 + 2.0 * i, (i % 2) ? 1.0 : -1.0, 1.0}, 0.0});
  const auto vps = in.viewpoints;
  int far_pairs = 0;
  in.path_length_m = [&](int a, int b) {
    if (b == 29 || a == 29) return kUnreachable;  // one viewpoint nobody reaches
    if (a != kRobotNode && b != kRobotNode && (a >= 10 || b >= 10)) ++far_pairs;
    const Eigen::Vector3d pa =
        a == kRobotNode ? in.robot.position_world_m : vps[a].position_world_m;
    const Eigen::Vector3d pb =
        b == kRobotNode ? in.robot.position_world_m : vps[b].position_world_m;
    return (pa - pb).norm();
  };
  HierarchicalPlannerConfig c;
  c.tour_searched_viewpoints = 10;
  c.prior_free_max_viewpoints = 20;
  const PlanningResult r = HierarchicalPlanner(c).plan(in);
  ASSERT_EQ(r.status, PlanningStatus::kOk);
  EXPECT_EQ(r.mode_used, BaselineMode::kPriorFree);
  ASSERT_EQ(r.tour.viewpoints.size(), 20u);
  for (int v : r.tour.viewpoints) EXPECT_LT(v, 20);
  EXPECT_EQ(r.tour.viewpoints.front(), 0);  // along the line, nearest first
  EXPECT_EQ(far_pairs, 0);
  EXPECT_EQ(r.tour.unreachable_viewpoints, std::vector<int>{29});
  // By default every reachable viewpoint is toured, the far ones with estimated lengths.
  c.prior_free_max_viewpoints = HierarchicalPlannerConfig().prior_free_max_viewpoints;
  const PlanningResult all = HierarchicalPlanner(c).plan(in);
  EXPECT_EQ(all.tour.viewpoints.size(), 29u);
  EXPECT_EQ(all.tour.unreachable_viewpoints, std::vector<int>{29});
  EXPECT_EQ(far_pairs, 0);
  c.tour_searched_viewpoints = 0;
  EXPECT_THROW(HierarchicalPlanner{c}, ConfigError);
  c.tour_searched_viewpoints = 10;
  c.prior_free_max_viewpoints = 0;
  EXPECT_THROW(HierarchicalPlanner{c}, ConfigError);
}

// With warm_start_tours the last plan's order survives a plan in which the other order costs the
// same: viewpoints on a line, 8 each side; the first plan is made 0.5 m east (east first is
// shorter), the second from the middle (a tie). Without it, the second plan's answer does not
// depend on the first.
TEST(HierarchicalPlanner, AWarmStartKeepsTheLastTourThroughATie) {
  PlanningInput in;
  for (int k = 1; k <= 8; ++k) {
    in.viewpoints.push_back(PlanViewpoint{100 + k, {-2.0 * k, 0.0, 1.0}, 0.0});
    in.viewpoints.push_back(PlanViewpoint{200 + k, {2.0 * k, 0.0, 1.0}, 0.0});
  }
  const auto vps = in.viewpoints;
  in.path_length_m = [&](int a, int b) {
    const Eigen::Vector3d pa =
        a == kRobotNode ? in.robot.position_world_m : vps[a].position_world_m;
    const Eigen::Vector3d pb =
        b == kRobotNode ? in.robot.position_world_m : vps[b].position_world_m;
    return (pa - pb).norm();
  };
  const auto firstXAfter = [&](bool warm, double first_x_m) {
    HierarchicalPlannerConfig c;
    c.warm_start_tours = warm;
    HierarchicalPlanner planner(c);
    in.robot.position_world_m = Eigen::Vector3d(first_x_m, 0.0, 1.0);
    const PlanningResult first = planner.plan(in);
    EXPECT_EQ(first.status, PlanningStatus::kOk);
    EXPECT_EQ(vps[first.tour.viewpoints.front()].position_world_m.x() > 0.0, first_x_m > 0.0);
    in.robot.position_world_m = Eigen::Vector3d(0.0, 0.0, 1.0);
    const PlanningResult tie = planner.plan(in);
    EXPECT_EQ(tie.tour.viewpoints.size(), vps.size());
    return vps[tie.tour.viewpoints.front()].position_world_m.x();
  };
  EXPECT_GT(firstXAfter(true, 0.5), 0.0);
  EXPECT_LT(firstXAfter(true, -0.5), 0.0);
  EXPECT_EQ(firstXAfter(false, 0.5) > 0.0, firstXAfter(false, -0.5) > 0.0);
}

// A viewpoint 1 m inside each end of a corridor(n) prior (x = 0 .. 20 (n - 1)).
Scene workAtBothEnds(const GuidepointPrior& corridor_prior) {
  Scene sc;
  const double far_x_m = corridor_prior.positions_sketch_m.back().x();
  sc.vps = {PlanViewpoint{0, {1.0, 0.0, 1.0}, 0.0},
            PlanViewpoint{1, {far_x_m - 1.0, 0.0, 1.0}, 0.0}};
  return sc;
}

// The first guidepoint of a guided plan made with the robot at (x_m, 0, 1) in scene `sc` over
// `prior`, by a planner that keeps what it remembers between calls (one hypothesis, scale 1).
int firstGuidepointFrom(HierarchicalPlanner& planner, const GuidepointPrior& prior, Scene& sc,
                        double x_m) {
  sc.robot.position_world_m = {x_m, 0.0, 1.0};
  PlanningInput in = sc.input();
  in.prior = &prior;
  in.hypotheses = {Hypothesis{4, Sim2(), 1.0}};
  const PlanningResult r = planner.plan(in);
  EXPECT_EQ(r.mode_used, BaselineMode::kProposed);
  EXPECT_EQ(r.selection.guidepoint_sequence.size(), static_cast<size_t>(prior.size()));
  return r.selection.guidepoint_sequence.empty() ? -1 : r.selection.guidepoint_sequence.front();
}

// keep_first_guidepoint_fraction: a corridor of 5 guidepoints (x = 0 .. 80) with work at both
// ends and the robot near the middle. 0.5 m east of it the east end comes first; 0.5 m west the
// west end is 1 m shorter in about 119 m, a near tie: with 3 % the east end stays first, without
// it the planner turns round. 5 m west (a 10 m gap) it turns round either way.
TEST(HierarchicalPlanner, TheLastFirstGuidepointStaysThroughANearTie) {
  const GuidepointPrior prior = corridor(5);
  Scene sc = workAtBothEnds(prior);
  const auto firstAfter = [&](double fraction, double second_x_m) {
    HierarchicalPlannerConfig c;
    c.keep_first_guidepoint_fraction = fraction;
    HierarchicalPlanner planner(c);
    EXPECT_EQ(firstGuidepointFrom(planner, prior, sc, 40.5), 4);
    return firstGuidepointFrom(planner, prior, sc, second_x_m);
  };
  EXPECT_EQ(firstAfter(0.03, 39.5), 4);
  EXPECT_EQ(firstAfter(0.0, 39.5), 0);
  EXPECT_EQ(firstAfter(0.03, 35.5), 0);
  HierarchicalPlannerConfig bad;
  bad.keep_first_guidepoint_fraction = -0.1;
  EXPECT_THROW(bad.validate(), ConfigError);
}

// warm_start_sequences: a corridor of 21 guidepoints (x = 0 .. 400, beyond the exact solver)
// with work at both ends and the robot in the middle. 0.5 m east of it the east end comes first,
// 0.5 m west the west end; from the middle both sequences are 599 m long. With the warm start
// the second plan keeps the first plan's end; without it (every plan solved afresh) its answer
// does not depend on the first plan.
TEST(HierarchicalPlanner, AWarmStartedSequenceKeepsItsFirstGuidepointThroughATie) {
  const GuidepointPrior prior = corridor(21);
  Scene sc = workAtBothEnds(prior);
  const auto firstAfter = [&](bool warm, double first_x_m) {
    HierarchicalPlannerConfig c;
    c.warm_start_sequences = warm;
    c.reuse_sequences = false;  // the memo would answer the second plan from the first
    HierarchicalPlanner planner(c);
    EXPECT_EQ(firstGuidepointFrom(planner, prior, sc, first_x_m), first_x_m > 200.0 ? 20 : 0);
    return firstGuidepointFrom(planner, prior, sc, 200.0);
  };
  EXPECT_EQ(firstAfter(true, 200.5), 20);
  EXPECT_EQ(firstAfter(true, 199.5), 0);
  EXPECT_EQ(firstAfter(false, 200.5), firstAfter(false, 199.5));
}

// The guided tour bounds its searches likewise: with 24 viewpoints around the first guidepoint
// and the robot beside them, only pairs among the 6 nearest are searched, the rest estimated.
TEST(HierarchicalPlanner, GuidedTourSearchesLengthsAmongTheNearestViewpointsOnly) {
  const GuidepointPrior prior = corridor(6);
  Scene sc;
  sc.robot.position_world_m = {8.0, 0.0, 1.0};
  for (int k = 0; k < 24; ++k)
    sc.vps.push_back(PlanViewpoint{k, {0.25 * k, k % 2 == 0 ? 1.0 : -1.0, 1.0}, 0.0});
  PlanningInput in = sc.input();
  in.prior = &prior;
  in.hypotheses = {Hypothesis{7, Sim2(), 0.8}};
  const auto exact = in.path_length_m;
  std::vector<std::pair<int, int>> searched;
  in.path_length_m = [&](int a, int b) {
    if (a != kRobotNode && b != kRobotNode) searched.emplace_back(a, b);
    return exact(a, b);
  };
  const auto plan = [&](int n_searched) {
    searched.clear();
    HierarchicalPlannerConfig c;
    c.tour_searched_viewpoints = n_searched;
    c.reuse_sequences = false;
    return HierarchicalPlanner(c).plan(in);
  };
  const PlanningResult r = plan(6);
  ASSERT_EQ(r.status, PlanningStatus::kOk);
  ASSERT_EQ(r.mode_used, BaselineMode::kProposed);
  std::vector<int> members = r.selection.isolated_viewpoints;
  members.insert(members.end(), r.selection.target_viewpoints.begin(),
                 r.selection.target_viewpoints.end());
  ASSERT_GT(members.size(), 12u);
  EXPECT_EQ(r.tour.viewpoints.size(), members.size());  // every one toured all the same
  std::sort(members.begin(), members.end(),
            [&](int a, int b) { return exact(kRobotNode, a) < exact(kRobotNode, b); });
  const std::vector<int> nearest(members.begin(), members.begin() + 6);
  const auto isNear = [&](int v) {
    return std::find(nearest.begin(), nearest.end(), v) != nearest.end();
  };
  int far = 0;
  for (const auto& [a, b] : searched) far += !isNear(a) || !isNear(b);
  EXPECT_EQ(far, 0);
  // Unbounded, the far pairs are searched.
  plan(1000);
  far = 0;
  for (const auto& [a, b] : searched) far += !isNear(a) || !isNear(b);
  EXPECT_GT(far, 0);
}

// The robot in a passage with 8 m of frontiers ahead (+x) and 58 m behind. The whole tour goes
// ahead first; one over the 10 nearest only sees 2 m behind and turns back (the paper-size cave
// livelock: the side it turns to changes as the robot moves).
TEST(HierarchicalPlanner, PriorFreeTourWeighsTheViewpointsBeyondTheSearchedOnes) {
  PlanningInput in;
  in.robot.position_world_m = Eigen::Vector3d(0, 0, 1);
  for (int x = 1; x <= 8; ++x) in.viewpoints.push_back(PlanViewpoint{x, {x + 0.0, 0, 1}, 0.0});
  for (int x = -3; x >= -60; --x)
    in.viewpoints.push_back(PlanViewpoint{100 - x, {x + 0.0, 0, 1}, 0.0});
  const auto vps = in.viewpoints;
  const Eigen::Vector3d robot = in.robot.position_world_m;
  in.path_length_m = [&](int a, int b) {
    const Eigen::Vector3d pa = a == kRobotNode ? robot : vps[a].position_world_m;
    const Eigen::Vector3d pb = b == kRobotNode ? robot : vps[b].position_world_m;
    return (pa - pb).norm();
  };
  const auto first_x = [&](const HierarchicalPlannerConfig& c) {
    const PlanningResult r = HierarchicalPlanner(c).plan(in);
    EXPECT_EQ(r.status, PlanningStatus::kOk);
    EXPECT_FALSE(r.tour.viewpoints.empty());
    return r.tour.viewpoints.empty() ? 0.0 : vps[r.tour.viewpoints.front()].position_world_m.x();
  };
  HierarchicalPlannerConfig c;
  c.tour_searched_viewpoints = 10;
  EXPECT_GT(first_x(c), 0.0);
  c.prior_free_max_viewpoints = 10;  // the tour over the searched ones alone
  EXPECT_LT(first_x(c), 0.0);
  // The estimate: exact along one passage away from the robot, a lower bound otherwise.
  EXPECT_DOUBLE_EQ(tourEdgeEstimate_m({10, 0, 0}, 10.0, {30, 0, 0}, 30.0), 20.0);
  EXPECT_DOUBLE_EQ(tourEdgeEstimate_m({10, 0, 0}, 10.0, {14, 3, 0}, 25.0), 15.0);
  EXPECT_DOUBLE_EQ(tourEdgeEstimate_m({10, 0, 0}, 10.0, {-10, 0, 0}, 10.0), 20.0);
}

}  // namespace
}  // namespace efs::planner
