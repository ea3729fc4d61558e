// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <random>

#include "prior_guided_planner/sequence_memo.h"

namespace efs::planner {
namespace {

// Guidepoints scattered over a 60 m square, straight-line costs times `scale`; the robot's row
// from `robot_xy`. Nodes 1, 3, 5, ... are exploring.
GuidepointProblem scattered(int n, uint64_t seed, const Eigen::Vector2d& robot_xy,
                            double scale = 1.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 60.0);
  std::vector<Eigen::Vector2d> p(n + 1, robot_xy);
  for (int i = 1; i <= n; ++i) p[i] = {u(rng), u(rng)};
  GuidepointProblem g;
  g.node_guidepoint.push_back(-1);
  for (int i = 1; i <= n; ++i) g.node_guidepoint.push_back(10 + i);
  g.problem.cost = CostMatrix(n + 1, 0.0);
  g.problem.exploring.assign(n + 1, false);
  for (int a = 1; a <= n; ++a) g.problem.exploring[a] = (a % 2 == 1);
  for (int a = 0; a <= n; ++a) {
    for (int b = 1; b <= n; ++b) {
      if (a == b) continue;
      const double d = (p[a] - p[b]).norm();
      g.problem.cost(a, b) = a == 0 ? (g.problem.exploring[b] ? d : kUnreachable) : scale * d;
    }
  }
  return g;
}

void expectSameOutcome(const MctsResult& got, const MctsResult& want) {
  ASSERT_TRUE(got.feasible);
  EXPECT_NEAR(got.length, want.length, 1e-9);
  ASSERT_EQ(got.best_length_by_first.size(), want.best_length_by_first.size());
  for (size_t j = 1; j < want.best_length_by_first.size(); ++j) {
    if (want.best_length_by_first[j] < kUnreachable)
      EXPECT_NEAR(got.best_length_by_first[j], want.best_length_by_first[j], 1e-9) << j;
    else
      EXPECT_EQ(got.best_length_by_first[j], kUnreachable) << j;  // not exploring
  }
}

// With 8 guidepoints every rollout's ATSP is solved exactly, so each remembered completion is
// the best one: the recalled result for a moved robot (or another scale) is the optimum.
TEST(SequenceMemo, RobotMovedGivesTheOptimumFromRememberedCompletions) {
  const MctsSequencer mcts;
  SequenceMemo memo;
  const GuidepointProblem before = scattered(8, 3, {0.0, 0.0});
  EXPECT_FALSE(memo.recall(before));
  memo.remember(before, mcts.solve(before.problem));
  for (const Eigen::Vector2d& robot : {Eigen::Vector2d(30.0, 30.0), Eigen::Vector2d(60.0, 5.0)}) {
    for (double scale : {1.0, 1.15}) {
      const GuidepointProblem moved = scattered(8, 3, robot, scale);
      const std::optional<MctsResult> kept = memo.recall(moved);
      ASSERT_TRUE(kept);
      EXPECT_EQ(kept->rollouts, 0);  // nothing was solved
      expectSameOutcome(*kept, solveSequenceExhaustive(moved.problem));
    }
  }
  EXPECT_EQ(memo.hits(), 4u);
  EXPECT_EQ(memo.misses(), 1u);
}

TEST(SequenceMemo, OtherGuidepointsOrStatesAreSolvedAgain) {
  SequenceMemo memo;
  const GuidepointProblem base = scattered(6, 5, {0.0, 0.0});
  memo.remember(base, MctsSequencer().solve(base.problem));
  GuidepointProblem state = base;
  state.problem.exploring[2] = true;  // an unexplored guidepoint became exploring
  state.problem.cost(0, 2) = 12.0;
  EXPECT_FALSE(memo.recall(state));
  GuidepointProblem other = base;
  other.node_guidepoint[3] = 99;  // another guidepoint in the problem
  EXPECT_FALSE(memo.recall(other));
  EXPECT_TRUE(memo.recall(base));
}

TEST(SequenceMemo, GuidepointReachableOnlyNowIsSolvedAgain) {
  SequenceMemo memo;
  GuidepointProblem cut_off = scattered(6, 7, {0.0, 0.0});
  cut_off.problem.cost(0, 3) = kUnreachable;  // exploring, but none of its viewpoints reachable
  const MctsResult r = MctsSequencer().solve(cut_off.problem);
  EXPECT_TRUE(r.best_sequence_by_first[3].empty());
  memo.remember(cut_off, r);
  EXPECT_TRUE(memo.recall(cut_off));
  EXPECT_FALSE(memo.recall(scattered(6, 7, {0.0, 0.0})));
}

TEST(SequenceMemo, KeepsTheMostRecentlyUsedProblems) {
  SequenceMemo memo(2);
  const MctsSequencer mcts;
  const GuidepointProblem a = scattered(5, 1, {0.0, 0.0});
  GuidepointProblem b = a, c = a;
  b.node_guidepoint[1] = 50;
  c.node_guidepoint[1] = 51;
  memo.remember(a, mcts.solve(a.problem));
  memo.remember(b, mcts.solve(b.problem));
  EXPECT_TRUE(memo.recall(a));  // a is now the most recent
  memo.remember(c, mcts.solve(c.problem));
  EXPECT_EQ(memo.size(), 2u);
  EXPECT_TRUE(memo.recall(a));
  EXPECT_TRUE(memo.recall(c));
  EXPECT_FALSE(memo.recall(b));
  EXPECT_THROW(SequenceMemo(0), std::invalid_argument);
}

TEST(SequenceMemo, NoGuidepointLeftIsRecalledAsTheEmptySequence) {
  SequenceMemo memo;
  GuidepointProblem none;
  none.node_guidepoint = {-1};
  none.problem.cost = CostMatrix(1, 0.0);
  none.problem.exploring = {false};
  memo.remember(none, MctsSequencer().solve(none.problem));
  const std::optional<MctsResult> r = memo.recall(none);
  ASSERT_TRUE(r);
  EXPECT_TRUE(r->feasible);
  EXPECT_TRUE(r->sequence.empty());
  EXPECT_EQ(r->length, 0.0);
}

}  // namespace
}  // namespace efs::planner
