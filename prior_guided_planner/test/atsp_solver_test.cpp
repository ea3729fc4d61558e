// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <numeric>
#include <random>
#include <thread>

#include "efs_common/config_check.h"
#include "prior_guided_planner/atsp_solver.h"

namespace efs::planner {
namespace {

CostMatrix randomMatrix(int n, uint64_t seed, double lo = 1.0, double hi = 100.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  CostMatrix c(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) c(i, j) = i == j ? 0.0 : u(rng);
  return c;
}

bool isPermutation(std::vector<int> v, int n) {
  if (static_cast<int>(v.size()) != n) return false;
  std::sort(v.begin(), v.end());
  for (int i = 0; i < n; ++i)
    if (v[i] != i) return false;
  return true;
}

// Brute force over all open paths start -> ... -> end.
double bruteOpen(const CostMatrix& c, int start, int end) {
  std::vector<int> mid;
  for (int i = 0; i < c.size(); ++i)
    if (i != start && i != end) mid.push_back(i);
  double best = kUnreachable;
  do {
    std::vector<int> p{start};
    p.insert(p.end(), mid.begin(), mid.end());
    if (end >= 0) p.push_back(end);
    best = std::min(best, pathCost(c, p, false));
  } while (std::next_permutation(mid.begin(), mid.end()));
  return best;
}

TEST(AtspSolver, HeldKarpMatchesBruteForce) {
  for (int n = 1; n <= 9; ++n)
    for (uint64_t s = 0; s < 5; ++s) {
      const CostMatrix c = randomMatrix(n, 100 * n + s);
      const AtspResult bf = solveAtspBruteForce(c), hk = solveAtspExact(c);
      EXPECT_NEAR(hk.cost, bf.cost, 1e-9) << "n=" << n << " seed=" << s;
      EXPECT_TRUE(isPermutation(hk.order, n));
      EXPECT_EQ(hk.order.front(), 0);
      EXPECT_NEAR(pathCost(c, hk.order, true), hk.cost, 1e-9);
    }
}

TEST(AtspSolver, LocalSearchFindsOptimumOnSmallInstances) {
  // Force the heuristic path (exact disabled) and compare with Held-Karp.
  AtspConfig cfg;
  cfg.exact_max_nodes = 0;
  const AtspSolver ils(cfg);
  int optimal = 0, total = 0;
  for (int n = 5; n <= 13; ++n)
    for (uint64_t s = 0; s < 4; ++s) {
      const CostMatrix c = randomMatrix(n, 7 * n + s);
      const AtspResult r = ils.solveTour(c), ex = solveAtspExact(c);
      ASSERT_TRUE(isPermutation(r.order, n));
      EXPECT_FALSE(r.exact);
      EXPECT_GE(r.cost, ex.cost - 1e-9);
      optimal += r.cost <= ex.cost + 1e-9;
      ++total;
    }
  EXPECT_EQ(optimal, total);
}

TEST(AtspSolver, DefaultIsExactUpTo13Nodes) {
  const AtspSolver solver;
  for (int n = 2; n <= 13; ++n) {
    const CostMatrix c = randomMatrix(n, n);
    const AtspResult r = solver.solveTour(c);
    EXPECT_TRUE(r.exact);
    EXPECT_NEAR(r.cost, solveAtspExact(c).cost, 1e-9);
  }
  EXPECT_FALSE(solver.solveTour(randomMatrix(14, 1)).exact);
}

TEST(AtspSolver, OpenPathWithFixedStartAndEnd) {
  AtspConfig heuristic;
  heuristic.exact_max_nodes = 0;
  for (const AtspSolver& solver : {AtspSolver(), AtspSolver(heuristic)})
    for (int n = 3; n <= 8; ++n)
      for (uint64_t s = 0; s < 3; ++s) {
        const CostMatrix c = randomMatrix(n, 31 * n + s);
        const int start = static_cast<int>(s % n), end = static_cast<int>((s + 2) % n);
        const AtspResult r = solver.solveOpenPath(c, start, end);
        ASSERT_TRUE(isPermutation(r.order, n));
        EXPECT_EQ(r.order.front(), start);
        EXPECT_EQ(r.order.back(), end);
        EXPECT_TRUE(r.feasible);
        EXPECT_NEAR(r.cost, bruteOpen(c, start, end), 1e-9) << "n=" << n;
        const AtspResult f = solver.solveOpenPath(c, start, AtspSolver::kFreeEnd);
        EXPECT_EQ(f.order.front(), start);
        EXPECT_NEAR(f.cost, bruteOpen(c, start, -1), 1e-9);
      }
}

TEST(AtspSolver, LargeOpenPathIsValid) {
  const CostMatrix c = randomMatrix(120, 5);
  const AtspResult r = AtspSolver().solveOpenPath(c, 7, 99);
  ASSERT_TRUE(isPermutation(r.order, 120));
  EXPECT_EQ(r.order.front(), 7);
  EXPECT_EQ(r.order.back(), 99);
  EXPECT_NEAR(pathCost(c, r.order, false), r.cost, 1e-6);
}

TEST(AtspSolver, LargeInstanceBeatsNearestNeighbourAndIsDeterministic) {
  const CostMatrix c = randomMatrix(100, 9);
  AtspConfig cfg;
  cfg.seed = 3;
  const AtspResult a = AtspSolver(cfg).solveTour(c), b = AtspSolver(cfg).solveTour(c);
  EXPECT_EQ(a.order, b.order);
  ASSERT_TRUE(isPermutation(a.order, 100));
  // Random uniform [1,100] ATSP: optimum ~ sum of row minima scale; NN is far worse.
  std::vector<int> nn{0};
  std::vector<char> used(100, 0);
  used[0] = 1;
  for (int k = 1; k < 100; ++k) {
    int best = -1;
    for (int j = 0; j < 100; ++j)
      if (!used[j] && (best < 0 || c(nn.back(), j) < c(nn.back(), best))) best = j;
    used[best] = 1;
    nn.push_back(best);
  }
  EXPECT_LT(a.cost, 0.8 * pathCost(c, nn, true));
}

TEST(AtspSolver, ToursAreValidAtEverySize) {
  // Small sizes make the moves wrap around the tour's buffer in every way.
  AtspConfig cfg;
  cfg.exact_max_nodes = 0;
  for (int n = 4; n <= 40; ++n) {
    const CostMatrix c = randomMatrix(n, 500 + n);
    const AtspResult r = AtspSolver(cfg).solveTour(c, n);
    ASSERT_TRUE(isPermutation(r.order, n)) << "n=" << n;
    EXPECT_NEAR(pathCost(c, r.order, true), r.cost, 1e-9) << "n=" << n;
    const AtspResult f = AtspSolver(cfg).solveOpenPath(c, n / 2, AtspSolver::kFreeEnd, n);
    ASSERT_TRUE(isPermutation(f.order, n));
    EXPECT_NEAR(pathCost(c, f.order, false), f.cost, 1e-9) << "n=" << n;
  }
}

TEST(AtspSolver, ChainsGiveTheSameTourHoweverTheyAreRun) {
  const CostMatrix c = randomMatrix(80, 12);
  AtspConfig cfg;
  cfg.chains = 3;
  const AtspSolver solver(cfg);
  const AtspResult in_order = solver.solveOpenPath(c, 4, AtspSolver::kFreeEnd, 7);
  const ParallelFor backwards = [](int jobs, const std::function<void(int)>& fn) {
    for (int j = jobs - 1; j >= 0; --j) fn(j);
  };
  const ParallelFor threads = [](int jobs, const std::function<void(int)>& fn) {
    std::vector<std::thread> t;
    for (int j = 0; j < jobs; ++j) t.emplace_back(fn, j);
    for (auto& x : t) x.join();
  };
  for (const ParallelFor* run : {&backwards, &threads}) {
    const AtspResult r = solver.solveOpenPath(c, 4, AtspSolver::kFreeEnd, 7, nullptr, run);
    EXPECT_EQ(r.order, in_order.order);
    EXPECT_EQ(r.cost, in_order.cost);
  }
  ASSERT_TRUE(isPermutation(in_order.order, 80));
  EXPECT_EQ(in_order.order.front(), 4);
  // The budget is shared, not multiplied.
  EXPECT_EQ(in_order.kicks, 3 * ((static_cast<int>(cfg.kicks_per_node * 80) + 2) / 3));
  // One chain is the unsplit search.
  cfg.chains = 1;
  const AtspResult one =
      AtspSolver(cfg).solveOpenPath(c, 4, AtspSolver::kFreeEnd, 7, nullptr, &threads);
  EXPECT_EQ(one.order, AtspSolver().solveOpenPath(c, 4, AtspSolver::kFreeEnd, 7).order);
}

TEST(AtspSolver, ChainedSearchStillFindsSmallOptima) {
  AtspConfig cfg;
  cfg.exact_max_nodes = 0;
  cfg.chains = 4;
  for (int n = 5; n <= 13; ++n)
    for (uint64_t s = 0; s < 3; ++s) {
      const CostMatrix c = randomMatrix(n, 11 * n + s);
      EXPECT_NEAR(AtspSolver(cfg).solveTour(c, s).cost, solveAtspExact(c).cost, 1e-9)
          << "n=" << n << " seed=" << s;
    }
}

TEST(AtspSolver, UnreachableEdgesAvoidedWhenPossibleAndReportedOtherwise) {
  CostMatrix c = randomMatrix(8, 2);
  // Forbid everything out of node 3 except 3 -> 5: every optimal tour uses it.
  for (int j = 0; j < 8; ++j)
    if (j != 3 && j != 5) c(3, j) = kUnreachable;
  AtspResult r = AtspSolver().solveTour(c);
  EXPECT_TRUE(r.feasible);
  const auto it = std::find(r.order.begin(), r.order.end(), 3);
  const size_t k = static_cast<size_t>(it - r.order.begin());
  EXPECT_EQ(r.order[(k + 1) % 8], 5);
  // Node 4 unreachable from everywhere: the tour exists but cannot be feasible.
  for (int i = 0; i < 8; ++i)
    if (i != 4) c(i, 4) = kUnreachable;
  r = AtspSolver().solveTour(c);
  EXPECT_FALSE(r.feasible);
  EXPECT_EQ(r.cost, kUnreachable);
  EXPECT_TRUE(isPermutation(r.order, 8));
}

TEST(AtspSolver, RejectsBadInputAndConfig) {
  CostMatrix c = randomMatrix(5, 1);
  c(1, 2) = std::nan("");
  EXPECT_THROW(AtspSolver().solveTour(c), std::invalid_argument);
  EXPECT_THROW(AtspSolver().solveOpenPath(randomMatrix(5, 1), 2, 2), std::invalid_argument);
  EXPECT_THROW(AtspSolver().solveOpenPath(randomMatrix(5, 1), 0, 5), std::invalid_argument);
  AtspConfig cfg;
  cfg.exact_max_nodes = 40;
  try {
    AtspSolver s(cfg);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("atsp.exact_max_nodes"), std::string::npos);
  }
  cfg = AtspConfig();
  cfg.chains = 0;
  EXPECT_THROW(AtspSolver{cfg}, ConfigError);
  EXPECT_TRUE(AtspSolver().solveTour(CostMatrix(0)).order.empty());
  EXPECT_EQ(AtspSolver().solveTour(CostMatrix(1)).order, std::vector<int>{0});
}

}  // namespace
}  // namespace efs::planner
