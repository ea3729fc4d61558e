// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// MCTS over prior guidepoints (paper Sec. VI-B). Node 0 of the problem is the robot (the root);
// nodes 1..n are the exploring and unexplored guidepoints of one hypothesis. A sequence visits
// every guidepoint once, starting from the robot, and ends anywhere (edges back to the robot
// are free). The first guidepoint must be an exploring one (the root expands only to those).
//
// One iteration = selection by UCB from the root down to a node with untried children,
// expansion of up to `rollouts_per_iteration` of them, one heavy rollout per new child (the
// remaining guidepoints completed by the ATSP solver: the paper's "simplified ATSP"), and
// backpropagation. The rollouts of one iteration run on `threads` std::threads; each rollout's
// seed depends only on the config seed and the tree node, so the result is the same for any
// thread count. The first iteration expands every child of the root so that every possible
// first guidepoint has a rollout length for the risk step (Sec. VI-C).
#pragma once

#include <cstdint>
#include <vector>

#include "prior_guided_planner/atsp_solver.h"
#include "prior_guided_planner/cost_matrix.h"

namespace efs::planner {

struct MctsConfig {
  /// UCB exploration constant C_u (paper Table: 1.414). Rewards are normalised by the root
  /// rollout's length so that the constant acts on rewards of order one.
  double exploration_constant = 1.414;
  int iterations = 20;
  int rollouts_per_iteration = 4;
  int threads = 1;
  /// Effort of each rollout's ATSP: warm-started from the parent's best completion, so far
  /// fewer kicks than a stand-alone solve (the root's rollout uses a default stand-alone solve).
  AtspConfig rollout;
  uint64_t seed = 1;

  MctsConfig() {
    rollout.kicks_per_node = 0.5;
    rollout.min_kicks = 30;
  }
  void validate() const;
};

struct MctsProblem {
  /// (n+1) x (n+1); row/column 0 is the robot. cost(i, 0) is ignored (free return); cost(0, j)
  /// of a non-exploring j is ignored (the root never expands to it).
  CostMatrix cost;
  /// Size n+1; exploring[0] is ignored.
  std::vector<bool> exploring;
};

struct MctsResult {
  /// Guidepoint nodes (1..n) in visiting order; empty when there is no guidepoint.
  std::vector<int> sequence;
  double length = kUnreachable;
  bool feasible = false;
  /// Per problem node (size n+1): the best sequence found that starts with that node and its
  /// length (kUnreachable if none); the intermediate results kept for CalcRisk.
  std::vector<double> best_length_by_first;
  std::vector<std::vector<int>> best_sequence_by_first;
  int rollouts = 0;
  int tree_nodes = 0;
};

class MctsSequencer {
 public:
  explicit MctsSequencer(MctsConfig config = {});
  /// Throws std::invalid_argument on a malformed problem (sizes, NaN).
  MctsResult solve(const MctsProblem& problem) const;
  const MctsConfig& config() const { return config_; }

 private:
  MctsConfig config_;
};

/// Exhaustive search over all sequences (n <= 9), for tests and benches.
MctsResult solveSequenceExhaustive(const MctsProblem& problem);

}  // namespace efs::planner
