// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The in-house asymmetric TSP solver (LKH may not be used: research-only licence).
//  - Exact Held-Karp dynamic programming up to `exact_max_nodes` nodes.
//  - Above that, iterated local search: start from the assignment relaxation (Hungarian
//    method) with its cycles patched together, candidate lists by reduced cost, a reversal-free
//    local search (segment swap = orientation-preserving 3-opt, which contains Or-opt, searched
//    over candidate neighbour lists with a work queue of "dirty" nodes) and random double-bridge
//    kicks (the orientation-preserving segment swap over random cuts), accepting equal or
//    better tours. Reversal-free moves keep the cost of every untouched edge, which is what
//    makes them safe on asymmetric matrices. The kicks may be split into independent chains
//    that share the start and run side by side; the best chain wins.
//  - Open paths with a fixed start and a fixed end through the standard dummy-node
//    transformation; a free end by making every edge back to the start free.
// Deterministic for a given seed; no clock is read: effort is a kick budget, not a time.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "prior_guided_planner/cost_matrix.h"

namespace efs::planner {

struct AtspConfig {
  /// Problems with at most this many nodes (open paths: real nodes, before the dummy) are
  /// solved exactly by dynamic programming. Memory is 2^(n-1) * n doubles.
  int exact_max_nodes = 13;
  /// Candidate neighbour list length for the local search (cheapest outgoing / incoming edges).
  int neighbours = 6;
  /// Kick budget of the iterated local search: kicks_per_node * n, clamped to [min, max].
  double kicks_per_node = 15.0;
  int min_kicks = 50;
  int max_kicks = 5000;
  /// Upper bound on the length of each of the two segments a kick swaps (local double bridge:
  /// short segments keep the repair local, which is what makes a kick cheap).
  int kick_segment_max = 30;
  /// Start from the assignment relaxation's cycle cover patched into one tour, and rank the
  /// candidate neighbours by its reduced costs; otherwise nearest neighbour and raw costs.
  bool assignment_start = true;
  /// The kick budget is shared by this many independent chains from the same local optimum
  /// (seeds derived from the solve's seed, chain 0 keeping it); the shortest tour wins, ties to
  /// the lower chain. Only the chain count changes the result, not how the chains are run.
  int chains = 1;
  uint64_t seed = 1;

  void validate() const;
};

/// Runs fn(0) .. fn(jobs - 1), possibly side by side, and returns when all have finished.
using ParallelFor = std::function<void(int jobs, const std::function<void(int)>& fn)>;

struct AtspResult {
  /// Closed tour: a permutation starting at node 0. Open path: start ... end (or free end).
  std::vector<int> order;
  /// Cost of `order` on the caller's matrix (a closed tour includes the closing edge); it is
  /// kUnreachable when no order avoids an unreachable edge.
  double cost = 0.0;
  bool feasible = true;
  bool exact = false;
  /// Kicks made, over all chains.
  int kicks = 0;
};

class AtspSolver {
 public:
  static constexpr int kFreeEnd = -1;

  explicit AtspSolver(AtspConfig config = {});

  /// Best closed tour through all nodes of `c` (square, no NaN, diagonal ignored). `parallel`,
  /// if given, runs the chains.
  AtspResult solveTour(const CostMatrix& c) const { return solveTour(c, config_.seed); }
  AtspResult solveTour(const CostMatrix& c, uint64_t seed,
                       const ParallelFor* parallel = nullptr) const;

  /// Best Hamiltonian path from `start` to `end` (kFreeEnd: ends anywhere).
  AtspResult solveOpenPath(const CostMatrix& c, int start, int end) const {
    return solveOpenPath(c, start, end, config_.seed);
  }
  /// `initial_order`, if given, is a warm start: a permutation of all nodes beginning with
  /// `start` (and ending with `end` when it is fixed); the assignment start is then skipped.
  AtspResult solveOpenPath(const CostMatrix& c, int start, int end, uint64_t seed,
                           const std::vector<int>* initial_order = nullptr,
                           const ParallelFor* parallel = nullptr) const;

  const AtspConfig& config() const { return config_; }

 private:
  AtspConfig config_;
};

/// Exact closed tour by Held-Karp (n <= 16); order starts at node 0. Exposed for tests/benches.
AtspResult solveAtspExact(const CostMatrix& c);

/// Exhaustive search over all permutations (n <= 10); for tests only.
AtspResult solveAtspBruteForce(const CostMatrix& c);

}  // namespace efs::planner
