// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "efs_common/config_check.h"
#include "prior_guided_planner/sequence_selection.h"

namespace efs::planner {
namespace {

HypothesisAttachment att(std::vector<int> attached_to, int guidepoints) {
  HypothesisAttachment a;
  a.attached_to = attached_to;
  a.attached.assign(guidepoints, {});
  a.states.assign(guidepoints, GuidepointState::kUnexplored);
  a.guidepoints_world_m.assign(guidepoints, Eigen::Vector2d::Zero());
  for (size_t v = 0; v < attached_to.size(); ++v)
    if (attached_to[v] >= 0) {
      a.attached[attached_to[v]].push_back(static_cast<int>(v));
      a.states[attached_to[v]] = GuidepointState::kExploring;
    }
  return a;
}

// A hypothesis whose problem nodes 1, 2 are guidepoints 0, 1 with the given best lengths per
// first guidepoint (kUnreachable: no rollout).
HypothesisSequence seq(double conf, double first0, double first1) {
  HypothesisSequence h;
  h.confidence = conf;
  h.problem.node_guidepoint = {-1, 0, 1};
  h.mcts.best_length_by_first = {kUnreachable, first0, first1};
  h.mcts.best_sequence_by_first = {{}, {}, {}};
  if (first0 < kUnreachable) h.mcts.best_sequence_by_first[1] = {1, 2};
  if (first1 < kUnreachable) h.mcts.best_sequence_by_first[2] = {2, 1};
  h.mcts.length = std::min(first0, first1);
  h.mcts.sequence = first0 <= first1 ? std::vector<int>{1, 2} : std::vector<int>{2, 1};
  h.mcts.feasible = true;
  return h;
}

// Viewpoints: v0, v1 attached to G0 under both hypotheses (group A), v2 attached to G1 only under
// hypothesis 0 (group B), v3 attached nowhere (isolated group C).
std::vector<ViewpointGroup> groups() {
  return groupViewpoints({att({0, 0, 1, -1}, 2), att({0, 0, -1, -1}, 2)}, 4);
}

PlanViewpoint at(double x, double y) {
  PlanViewpoint v;
  v.position_world_m = {x, y, 1.5};
  return v;
}

// Robot at the origin, the way leads to (20, 0). v0 (10, 2) and v1 (-5, 0) belong to G0, which
// the seen rule counted explored; v2 to G1, still exploring; v3 to G0 but out of reach. v0
// lengthens the way by 0.4 m (10.2 + 10.2 - 20), v1 by 10 m (5 + 25 - 20).
TEST(SequenceSelection, LeftoversOnTheWayAreThoseOfSeenGuidepointsWithASmallDetour) {
  HypothesisAttachment a = att({0, 0, 1, 0}, 2);
  a.states[0] = GuidepointState::kExplored;
  const std::vector<PlanViewpoint> vps = {at(10, 2), at(-5, 0), at(12, 0), at(11, 1)};
  const std::vector<double> robot_len = {std::hypot(10.0, 2.0), 5.0, 12.0, kUnreachable};
  const auto taken = [&](double detour_m) {
    return leftoversOnTheWay(a, vps, robot_len, {0, 0}, {20, 0}, detour_m);
  };
  EXPECT_EQ(taken(1.0), (std::vector<int>{0}));
  EXPECT_EQ(taken(10.5), (std::vector<int>{0, 1}));
  EXPECT_TRUE(taken(0.0).empty());            // off
  a.states[0] = GuidepointState::kExploring;  // the paper's states: no leftovers
  EXPECT_TRUE(taken(10.5).empty());
  EXPECT_THROW(leftoversOnTheWay(a, vps, {5.0}, {0, 0}, {20, 0}, 1.0), std::invalid_argument);
}

// The kept first guidepoint's sequence is credited with a share of the best length: enough to
// win a near tie, not a clear loss; a guidepoint that is no longer exploring gets nothing.
TEST(SequenceSelection, AKeptFirstGuidepointWinsANearTieOnly) {
  const auto credited = [](double first0, double first1, int kept, double fraction) {
    HypothesisSequence h = seq(1.0, first0, first1);
    h.problem.problem.exploring = {false, true, true};
    creditKeptFirstGuidepoint(h, kept, fraction);
    return h;
  };
  // G1 first is 100 m, G0 first 102 m; the last plan went to G0; 3 % of 100 m is 3 m.
  const HypothesisSequence kept = credited(102.0, 100.0, 0, 0.03);
  EXPECT_EQ(kept.mcts.sequence, (std::vector<int>{1, 2}));
  EXPECT_DOUBLE_EQ(kept.mcts.length, 99.0);
  EXPECT_DOUBLE_EQ(kept.mcts.best_length_by_first[1], 99.0);
  EXPECT_DOUBLE_EQ(kept.mcts.best_length_by_first[2], 100.0);
  // 110 m against 100 m: 3 m do not make up the difference.
  const HypothesisSequence lost = credited(110.0, 100.0, 0, 0.03);
  EXPECT_EQ(lost.mcts.sequence, (std::vector<int>{2, 1}));
  EXPECT_DOUBLE_EQ(lost.mcts.length, 100.0);
  EXPECT_DOUBLE_EQ(lost.mcts.best_length_by_first[1], 107.0);
  // Kept guidepoint unknown to the problem, no fraction: unchanged.
  for (const HypothesisSequence& h :
       {credited(102.0, 100.0, 7, 0.03), credited(102.0, 100.0, 0, 0.0)}) {
    EXPECT_EQ(h.mcts.sequence, (std::vector<int>{2, 1}));
    EXPECT_DOUBLE_EQ(h.mcts.best_length_by_first[1], 102.0);
  }
  // G0 no longer exploring (the root cannot start there): unchanged.
  HypothesisSequence idle = seq(1.0, 102.0, 100.0);
  idle.problem.problem.exploring = {false, false, true};
  creditKeptFirstGuidepoint(idle, 0, 0.03);
  EXPECT_EQ(idle.mcts.sequence, (std::vector<int>{2, 1}));
}

TEST(SequenceSelection, GroupVps) {
  const auto g = groups();
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g[0].viewpoints, (std::vector<int>{0, 1}));
  EXPECT_EQ(g[1].viewpoints, (std::vector<int>{2}));
  EXPECT_EQ(g[2].viewpoints, (std::vector<int>{3}));
  EXPECT_FALSE(g[0].isolated());
  EXPECT_TRUE(g[2].isolated());
}

TEST(SequenceSelection, RiskIsConfidenceWeightedExtraLength) {
  // H0 (conf 0.6) prefers G1 first (100 vs 140); H1 (conf 0.4) has only G0 attached.
  const std::vector<HypothesisSequence> s = {seq(0.6, 140.0, 100.0), seq(0.4, 80.0, kUnreachable)};
  const std::vector<double> robot_len = {5.0, 7.0, 10.0, 3.0};
  const std::vector<double> risk = calcRisk(groups(), s, robot_len);
  EXPECT_NEAR(risk[0], 0.6 * 40.0 + 0.4 * 0.0, 1e-12);
  // Group B is not attached under H1: the detour there and back, 2 * 10 m.
  EXPECT_NEAR(risk[1], 0.6 * 0.0 + 0.4 * 20.0, 1e-12);
  EXPECT_EQ(risk[2], kUnreachable);
  const PriorSelection sel = selectPriorSequence(groups(), s, robot_len);
  EXPECT_EQ(sel.group, 1);
  EXPECT_EQ(sel.hypothesis, 0);
  EXPECT_EQ(sel.guidepoint_sequence, (std::vector<int>{1, 0}));
  EXPECT_EQ(sel.target_viewpoints, (std::vector<int>{2}));
  EXPECT_EQ(sel.isolated_viewpoints, (std::vector<int>{3}));
}

TEST(SequenceSelection, FarDetourTipsTheChoiceToTheSharedGroup) {
  const std::vector<HypothesisSequence> s = {seq(0.6, 140.0, 100.0), seq(0.4, 80.0, kUnreachable)};
  // v2 40 m away: B's risk 0.4 * 80 = 32 > A's 24.
  const PriorSelection sel = selectPriorSequence(groups(), s, {5.0, 7.0, 40.0, 3.0});
  EXPECT_EQ(sel.group, 0);
  EXPECT_EQ(sel.target_viewpoints, (std::vector<int>{0, 1}));
  // Both hypotheses attach A; only H1's best sequence starts there -> H1.
  EXPECT_EQ(sel.hypothesis, 1);
  EXPECT_EQ(sel.guidepoint_sequence, (std::vector<int>{0, 1}));
}

TEST(SequenceSelection, SameGroupGoesToTheMostConfidentSequence) {
  // Both hypotheses start with G0: pick the higher confidence (H1 here).
  const std::vector<HypothesisSequence> s = {seq(0.3, 90.0, 120.0), seq(0.7, 80.0, 130.0)};
  const PriorSelection sel = selectPriorSequence(groups(), s, {5.0, 7.0, 10.0, 3.0});
  EXPECT_EQ(sel.group, 0);
  EXPECT_EQ(sel.hypothesis, 1);
}

TEST(SequenceSelection, RiskTiesGoToTheHighestConfidence) {
  // Two groups, each attached under exactly one hypothesis, both at zero extra length for their
  // own hypothesis and with equal detours for the other: equal risk; H1 is more confident.
  const auto g = groupViewpoints({att({0, -1}, 2), att({-1, 1}, 2)}, 2);
  const std::vector<HypothesisSequence> s = {seq(0.5, 50.0, kUnreachable),
                                             seq(0.5, kUnreachable, 60.0)};
  PriorSelection sel = selectPriorSequence(g, s, {10.0, 10.0});
  EXPECT_NEAR(sel.risk[0], sel.risk[1], 1e-12);
  EXPECT_EQ(sel.group, 0);  // equal confidence: the first group
  // Confidences 0.4 / 0.6 with detours 30 m / 45 m: risks 0.6 * 30 = 0.4 * 45 = 18, a tie that
  // goes to group 1, attached by the more confident H1.
  std::vector<HypothesisSequence> s2 = s;
  s2[0].confidence = 0.4;
  s2[1].confidence = 0.6;
  sel = selectPriorSequence(g, s2, {15.0, 22.5});
  EXPECT_NEAR(sel.risk[0], 18.0, 1e-9);
  EXPECT_NEAR(sel.risk[1], 18.0, 1e-9);
  EXPECT_EQ(sel.group, 1);
  EXPECT_EQ(sel.hypothesis, 1);
}

TEST(SequenceSelection, SingleHypothesisBypassesRisk) {
  const auto g = groupViewpoints({att({0, 1, 1, -1}, 2)}, 4);
  const PriorSelection sel = selectPriorSequence(g, {seq(1.0, 140.0, 100.0)}, {1, 1, 1, 1});
  EXPECT_TRUE(sel.risk.empty());
  EXPECT_EQ(sel.guidepoint_sequence, (std::vector<int>{1, 0}));
  EXPECT_EQ(sel.target_viewpoints, (std::vector<int>{1, 2}));
  EXPECT_EQ(sel.isolated_viewpoints, (std::vector<int>{3}));
}

TEST(SequenceSelection, GuidepointProblemCosts) {
  GuidepointPrior prior;
  prior.positions_sketch_m = {{0, 0}, {10, 0}, {20, 0}, {30, 0}};
  prior.prm_distance_m = CostMatrix(4, 0.0);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) prior.prm_distance_m(i, j) = 12.0 * std::abs(i - j);
  prior.prm_distance_m(0, 3) = prior.prm_distance_m(3, 0) = kUnreachable;
  HypothesisAttachment a = att({0, 0, 2, -1}, 4);
  a.states[1] = GuidepointState::kExplored;  // explored guidepoints are not sequenced
  const std::vector<double> robot_len = {4.0, 8.0, kUnreachable, 1.0};
  const GuidepointProblem p = buildGuidepointProblem(a, prior, 2.0, robot_len, SequencingConfig{});
  EXPECT_EQ(p.node_guidepoint, (std::vector<int>{-1, 0, 2, 3}));
  EXPECT_EQ(p.problem.exploring, (std::vector<bool>{false, true, true, false}));
  EXPECT_NEAR(p.problem.cost(0, 1), 6.0, 1e-12);               // mean of 4 and 8
  EXPECT_EQ(p.problem.cost(0, 2), kUnreachable);               // its only viewpoint is unreachable
  EXPECT_EQ(p.problem.cost(0, 3), kUnreachable);               // unexplored: not from the root
  EXPECT_NEAR(p.problem.cost(1, 2), 2.0 * 24.0, 1e-12);        // scale * PRM
  EXPECT_NEAR(p.problem.cost(1, 3), 2.0 * 3.0 * 30.0, 1e-12);  // unconnected: penalised line
  EXPECT_EQ(p.problem.cost(2, 0), 0.0);
  EXPECT_THROW(buildGuidepointProblem(a, prior, std::nan(""), robot_len, {}),
               std::invalid_argument);
  EXPECT_THROW(buildGuidepointProblem(a, prior, -1.0, robot_len, {}), std::invalid_argument);
}

}  // namespace
}  // namespace efs::planner
