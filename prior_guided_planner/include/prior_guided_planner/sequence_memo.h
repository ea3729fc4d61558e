// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The MCTS sequencing of a hypothesis' guidepoints (Sec. VI-B), reused from one plan to the
// next while its problem is the same but for the robot's row. The planner replans 2-3 times a
// second, and most plans leave every guidepoint's state as it was: only the robot moved. Each
// rollout completes the guidepoints after its first one with an ATSP, and those completions
// never depend on the robot: the robot -> guidepoint costs enter once, as the first leg. So the
// best completion found for each first guidepoint stays valid, and the best sequence for the
// moved robot is the cheapest first leg plus its completion, priced on the new matrix.
// Solving again took 49 % of all the CPU of the first 80 s of a paper-sized garage flight (233
// guidepoints, 3-4 hypotheses; perf), about 0.5 s per plan; mcts_bench's planning cycle takes
// 34 ms solved and 0.08 ms reused.
//
// A problem matches a remembered one when it has the same guidepoints (problem nodes) in the
// same states. Guidepoint-to-guidepoint costs then differ at most by the hypothesis' scale
// (scale * PRM distance), which changes the lengths but not which completion is shortest; the
// lengths are re-priced on the new matrix. A guidepoint the robot could not reach before but
// can now has no remembered completion: that problem is solved again.
#pragma once

#include <cstddef>
#include <list>
#include <optional>
#include <vector>

#include "prior_guided_planner/mcts_sequencer.h"
#include "prior_guided_planner/sequence_selection.h"

namespace efs::planner {

class SequenceMemo {
 public:
  /// Remembers the results of up to `capacity` distinct problems (least recently used dropped).
  explicit SequenceMemo(size_t capacity = 8);

  /// The remembered result re-priced for `problem`, or std::nullopt when none matches.
  std::optional<MctsResult> recall(const GuidepointProblem& problem);
  /// Keeps `result`, the MCTS outcome of `problem`.
  void remember(const GuidepointProblem& problem, const MctsResult& result);

  size_t size() const { return entries_.size(); }
  size_t hits() const { return hits_; }
  size_t misses() const { return misses_; }

 private:
  struct Entry {
    std::vector<int> node_guidepoint;
    std::vector<bool> exploring;
    /// Per problem node: the best sequence found that starts there (empty if none).
    std::vector<std::vector<int>> sequence_by_first;
  };
  /// The entry of the same guidepoints in the same states (at most one), or end().
  std::list<Entry>::iterator find(const GuidepointProblem& problem);

  size_t capacity_;
  std::list<Entry> entries_;  ///< most recently used first
  size_t hits_ = 0, misses_ = 0;
};

}  // namespace efs::planner
