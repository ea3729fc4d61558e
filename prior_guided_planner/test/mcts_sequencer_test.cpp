// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <thread>

#include "efs_common/config_check.h"
#include "prior_guided_planner/mcts_sequencer.h"

namespace efs::planner {
namespace {

MctsProblem randomProblem(int n, int exploring, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(1.0, 100.0);
  MctsProblem p;
  p.cost = CostMatrix(n + 1);
  p.exploring.assign(n + 1, false);
  for (int k = 1; k <= exploring; ++k) p.exploring[1 + (k * 7 + static_cast<int>(seed)) % n] = true;
  for (int i = 0; i <= n; ++i)
    for (int j = 1; j <= n; ++j)
      if (i != j) p.cost(i, j) = u(rng);
  return p;
}

double sequenceLength(const MctsProblem& p, const std::vector<int>& s) {
  double len = p.cost(0, s.front());
  for (size_t k = 0; k + 1 < s.size(); ++k) len += p.cost(s[k], s[k + 1]);
  return len;
}

TEST(MctsSequencer, FindsTheExhaustiveOptimumOnSmallInstances) {
  // Sequentially and on kept workers with more threads than rollouts in some batches.
  MctsConfig parallel;
  parallel.threads = 4;
  parallel.root_chains = 3;
  for (const MctsSequencer& mcts : {MctsSequencer(), MctsSequencer(parallel)})
    for (int n = 2; n <= 8; ++n)
      for (uint64_t s = 0; s < 4; ++s) {
        const MctsProblem p = randomProblem(n, 1 + static_cast<int>(s % 3), 13 * n + s);
        const MctsResult r = mcts.solve(p), ex = solveSequenceExhaustive(p);
        ASSERT_TRUE(r.feasible);
        EXPECT_NEAR(r.length, ex.length, 1e-9)
            << "n=" << n << " seed=" << s << " threads=" << mcts.config().threads;
        // A valid sequence: every guidepoint once, the first one exploring.
        std::vector<int> sorted = r.sequence;
        std::sort(sorted.begin(), sorted.end());
        for (int k = 0; k < n; ++k) EXPECT_EQ(sorted[k], k + 1);
        EXPECT_TRUE(p.exploring[r.sequence.front()]);
        EXPECT_NEAR(sequenceLength(p, r.sequence), r.length, 1e-9);
        // The per-first-guidepoint lengths kept for the risk step are exact here (rollouts on
        // <= 13 nodes are solved by dynamic programming).
        for (int g = 1; g <= n; ++g) {
          if (!p.exploring[g]) {
            EXPECT_EQ(r.best_length_by_first[g], kUnreachable);
            continue;
          }
          EXPECT_NEAR(r.best_length_by_first[g], ex.best_length_by_first[g], 1e-9);
          EXPECT_EQ(r.best_sequence_by_first[g].front(), g);
        }
      }
}

TEST(MctsSequencer, ResultDoesNotDependOnThreadCount) {
  const MctsProblem p = randomProblem(40, 4, 99);
  MctsConfig c;
  c.iterations = 8;
  c.threads = 1;
  const MctsResult a = MctsSequencer(c).solve(p);
  c.threads = 3;
  const MctsResult b = MctsSequencer(c).solve(p);
  EXPECT_EQ(a.sequence, b.sequence);
  EXPECT_EQ(a.length, b.length);
  EXPECT_EQ(a.rollouts, b.rollouts);
  // Iteration 1 expands the whole root (4 exploring), then up to 4 per iteration.
  EXPECT_EQ(a.rollouts, 1 + 4 + 7 * 4);
}

void expectSameResult(const MctsResult& a, const MctsResult& b) {
  EXPECT_EQ(a.sequence, b.sequence);
  EXPECT_EQ(a.length, b.length);
  EXPECT_EQ(a.best_length_by_first, b.best_length_by_first);
  EXPECT_EQ(a.best_sequence_by_first, b.best_sequence_by_first);
  EXPECT_EQ(a.rollouts, b.rollouts);
  EXPECT_EQ(a.tree_nodes, b.tree_nodes);
}

TEST(MctsSequencer, RootChainsAndThreadsAreIndependent) {
  // 60 guidepoints: the root rollout is an ILS (not dynamic programming), split into chains.
  const MctsProblem p = randomProblem(60, 6, 17);
  MctsConfig c;
  c.iterations = 6;
  for (int chains : {1, 3}) {
    c.root_chains = chains;
    c.threads = 1;
    const MctsResult ref = MctsSequencer(c).solve(p);
    ASSERT_TRUE(ref.feasible);
    for (int threads : {2, 4}) {
      c.threads = threads;
      SCOPED_TRACE("chains " + std::to_string(chains) + ", threads " + std::to_string(threads));
      expectSameResult(MctsSequencer(c).solve(p), ref);
    }
  }
}

TEST(MctsSequencer, KeptWorkersGiveTheResultOfAFreshSequencer) {
  const MctsProblem a = randomProblem(40, 4, 3), b = randomProblem(25, 3, 4);
  MctsConfig c;
  c.iterations = 10;
  c.threads = 3;
  const MctsSequencer kept(c);
  const MctsResult a1 = kept.solve(a), b1 = kept.solve(b), a2 = kept.solve(a);
  expectSameResult(a1, MctsSequencer(c).solve(a));
  expectSameResult(b1, MctsSequencer(c).solve(b));
  expectSameResult(a2, a1);
  // A seed per call is the same as a sequencer configured with it.
  MctsConfig seeded = c;
  seeded.seed = 99;
  expectSameResult(kept.solve(a, 99), MctsSequencer(seeded).solve(a));
}

TEST(MctsSequencer, ConcurrentSolvesShareTheWorkers) {
  const MctsProblem p = randomProblem(30, 3, 8);
  MctsConfig c;
  c.iterations = 8;
  c.threads = 2;
  const MctsSequencer shared(c);
  const MctsResult ref = MctsSequencer(c).solve(p);
  std::vector<MctsResult> out(3);
  std::vector<std::thread> callers;
  for (size_t k = 0; k < out.size(); ++k)
    callers.emplace_back([&, k] { out[k] = shared.solve(p); });
  for (auto& t : callers) t.join();
  for (const MctsResult& r : out) expectSameResult(r, ref);
}

TEST(MctsSequencer, MoreIterationsNeverWorse) {
  const MctsProblem p = randomProblem(30, 3, 5);
  double prev = kUnreachable;
  for (int it : {1, 5, 20, 60}) {
    MctsConfig c;
    c.iterations = it;
    const double len = MctsSequencer(c).solve(p).length;
    EXPECT_LE(len, prev + 1e-9);
    prev = len;
  }
}

// The warm order keeps the previous sequence's order, drops what the problem no longer has (or
// never had), inserts the new guidepoint where it lengthens the path least and lets the first
// exploring guidepoint lead.
TEST(MctsSequencer, WarmRootOrderKeepsThePreviousOrderAndInsertsTheRest) {
  // Five guidepoints on a line at x = 10, 20, ..., 50 (node k at 10 k); the robot at x = 0.
  MctsProblem p;
  p.cost = CostMatrix(6);
  p.exploring = {false, false, true, false, true, false};
  for (int i = 0; i < 6; ++i)
    for (int j = 1; j < 6; ++j)
      if (i != j) p.cost(i, j) = 10.0 * std::abs(i - j);
  // 3 is missing: between 2 and 4 it costs nothing extra. 1 leads the previous order but is
  // not exploring, so 2 (the first exploring one) moves in front of it.
  EXPECT_EQ(warmRootOrder(p, {1, 2, 9, 4, 2, 0, -3, 5}), (std::vector<int>{0, 2, 1, 3, 4, 5}));
  // 5 -> 3 -> 2 -> 1 walks back along the line at no extra cost after 4, 5.
  EXPECT_EQ(warmRootOrder(p, {4, 5}), (std::vector<int>{0, 4, 5, 3, 2, 1}));
  // Nothing of the previous sequence left, or nothing exploring: no warm start.
  EXPECT_TRUE(warmRootOrder(p, {}).empty());
  EXPECT_TRUE(warmRootOrder(p, {7, 0}).empty());
  std::fill(p.exploring.begin(), p.exploring.end(), false);
  EXPECT_TRUE(warmRootOrder(p, {1, 2}).empty());
}

// Started from the previous plan's sequence, the root's search accepts only equal or shorter
// sequences, so the result is never longer than that sequence (40 guidepoints: beyond the exact
// solver, where the search is heuristic and each cold solve may end elsewhere).
TEST(MctsSequencer, AWarmStartIsNeverLengthened) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const MctsProblem p = randomProblem(40, 5, seed);
    const MctsResult cold = MctsSequencer().solve(p, seed);
    ASSERT_TRUE(cold.feasible);
    const MctsResult warm = MctsSequencer().solve(p, seed + 100, &cold.sequence);
    ASSERT_TRUE(warm.feasible);
    EXPECT_LE(warm.length, cold.length + 1e-9);
    EXPECT_NEAR(sequenceLength(p, warm.sequence), warm.length, 1e-9);
    EXPECT_TRUE(p.exploring[warm.sequence.front()]);
    // From a poor order (the guidepoints by number, exploring ones first) the search improves
    // on it, and the answer is still a valid sequence.
    std::vector<int> poor;
    for (int g = 1; g <= 40; ++g)
      if (p.exploring[g]) poor.push_back(g);
    for (int g = 1; g <= 40; ++g)
      if (!p.exploring[g]) poor.push_back(g);
    const MctsResult from_poor = MctsSequencer().solve(p, seed, &poor);
    EXPECT_LT(from_poor.length, sequenceLength(p, poor));
    std::vector<int> sorted = from_poor.sequence;
    std::sort(sorted.begin(), sorted.end());
    for (int k = 0; k < 40; ++k) EXPECT_EQ(sorted[k], k + 1);
  }
}

TEST(MctsSequencer, EdgeCasesAndBadInput) {
  // No guidepoint at all.
  MctsProblem empty;
  empty.cost = CostMatrix(1);
  empty.exploring = {false};
  MctsResult r = MctsSequencer().solve(empty);
  EXPECT_TRUE(r.sequence.empty());
  EXPECT_EQ(r.length, 0.0);
  // No exploring guidepoint: the root cannot expand, nothing feasible.
  MctsProblem p = randomProblem(5, 0, 1);
  std::fill(p.exploring.begin(), p.exploring.end(), false);
  r = MctsSequencer().solve(p);
  EXPECT_FALSE(r.feasible);
  // Malformed.
  p.exploring.pop_back();
  EXPECT_THROW(MctsSequencer().solve(p), std::invalid_argument);
  p = randomProblem(5, 1, 1);
  p.cost(2, 3) = std::nan("");
  EXPECT_THROW(MctsSequencer().solve(p), std::invalid_argument);
  const auto expectRejected = [](const MctsConfig& c, const std::string& key) {
    try {
      MctsSequencer s(c);
      ADD_FAILURE() << key << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  MctsConfig c;
  c.exploration_constant = -1.0;
  expectRejected(c, "mcts.exploration_constant");
  c = MctsConfig();
  c.threads = 0;
  expectRejected(c, "mcts.threads");
  c = MctsConfig();
  c.root_chains = 0;
  expectRejected(c, "mcts.root_chains");
}

}  // namespace
}  // namespace efs::planner
