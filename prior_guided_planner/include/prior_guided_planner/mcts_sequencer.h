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
// backpropagation. The rollouts of one iteration are independent jobs for a worker pool that
// the sequencer keeps between solves (`threads` - 1 workers plus the calling thread, each taking
// the next job as it becomes free). Each rollout's seed depends only on the solve's seed and the
// tree node, and the root rollout is split into a fixed number of chains, so the result is the
// same for any thread count. The first iteration expands every child of the root so that every
// possible first guidepoint has a rollout length for the risk step (Sec. VI-C).
#pragma once

#include <cstdint>
#include <memory>
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
  /// The root rollout (the largest ATSP of a solve, over every guidepoint) is split into this
  /// many independent ILS chains from the same start, the kick budget shared between them; the
  /// shortest wins. A fixed count rather than `threads`, so that the result does not depend on
  /// the thread count, while the chains still run side by side. Four chains came out at least
  /// as short on average as one on 30-100 random guidepoints (the MCTS rarely improves on the
  /// root's tour there), and give four threads a share each.
  int root_chains = 4;
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

class RolloutPool;

class MctsSequencer {
 public:
  explicit MctsSequencer(MctsConfig config = {});
  /// Throws std::invalid_argument on a malformed problem (sizes, NaN). Safe to call from several
  /// threads at once (their rollout batches take turns on the pool).
  MctsResult solve(const MctsProblem& problem) const { return solve(problem, config_.seed); }
  /// The same with another seed (e.g. one per hypothesis), reusing this sequencer's workers.
  /// `root_warm`, if given, starts the root rollout from that visiting order instead of the
  /// assignment relaxation (warmRootOrder); its entries are problem nodes, any subset.
  MctsResult solve(const MctsProblem& problem, uint64_t seed,
                   const std::vector<int>* root_warm = nullptr) const;
  const MctsConfig& config() const { return config_; }

 private:
  MctsConfig config_;
  /// Null for one thread; shared by copies of the sequencer.
  std::shared_ptr<RolloutPool> pool_;
};

/// The result of a problem of `nodes` nodes before any sequence is found: every per-node entry
/// unreachable. With no guidepoint (nodes == 1) it is already final: the empty sequence, length 0.
MctsResult initialMctsResult(int nodes);

/// The root rollout's warm start from a previous plan's sequence: `previous` (problem nodes;
/// unknown, repeated and robot entries dropped) in its order, the problem's other guidepoints
/// each put where it lengthens the sequence least, and the first exploring one moved to the
/// front (the root expands only to those). Returns the path 0, ..., over all nodes, or an empty
/// vector when no guidepoint of `previous` is left or none is exploring.
std::vector<int> warmRootOrder(const MctsProblem& problem, const std::vector<int>& previous);

/// Exhaustive search over all sequences (n <= 9), for tests and benches.
MctsResult solveSequenceExhaustive(const MctsProblem& problem);

}  // namespace efs::planner
