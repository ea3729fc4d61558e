// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/sequence_memo.h"

#include <algorithm>
#include <stdexcept>

namespace efs::planner {

SequenceMemo::SequenceMemo(size_t capacity) : capacity_(capacity) {
  if (capacity_ == 0) throw std::invalid_argument("SequenceMemo: capacity must be at least 1");
}

namespace {

// Sequence length on the problem's matrix: the robot's leg, then guidepoint to guidepoint.
double lengthOn(const MctsProblem& p, const std::vector<int>& sequence) {
  double len = p.cost(0, sequence.front());
  if (!(len < kUnreachable)) return kUnreachable;
  for (size_t k = 0; k + 1 < sequence.size(); ++k) {
    const double edge = p.cost(sequence[k], sequence[k + 1]);
    if (!(edge < kUnreachable)) return kUnreachable;
    len += edge;
  }
  return len;
}

}  // namespace

std::list<SequenceMemo::Entry>::iterator SequenceMemo::find(const GuidepointProblem& gp) {
  return std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) {
    return e.node_guidepoint == gp.node_guidepoint && e.exploring == gp.problem.exploring;
  });
}

std::optional<MctsResult> SequenceMemo::recall(const GuidepointProblem& gp) {
  const MctsProblem& p = gp.problem;
  const int m = p.cost.size();
  const auto it = find(gp);
  if (it == entries_.end()) {
    ++misses_;
    return std::nullopt;
  }
  MctsResult r = initialMctsResult(m);
  for (int j = 1; j < m; ++j) {
    if (!p.exploring[j] || !(p.cost(0, j) < kUnreachable)) continue;
    const std::vector<int>& s = it->sequence_by_first[j];
    if (s.empty()) {  // reachable now, no completion remembered
      ++misses_;
      return std::nullopt;
    }
    r.best_length_by_first[j] = lengthOn(p, s);
    r.best_sequence_by_first[j] = s;
    if (r.best_length_by_first[j] < r.length) r.length = r.best_length_by_first[j], r.sequence = s;
  }
  if (m > 1) r.feasible = !r.sequence.empty() && r.length < kUnreachable;
  entries_.splice(entries_.begin(), entries_, it);
  ++hits_;
  return r;
}

void SequenceMemo::remember(const GuidepointProblem& gp, const MctsResult& result) {
  const auto it = find(gp);
  if (it != entries_.end()) entries_.erase(it);
  entries_.push_front(
      Entry{gp.node_guidepoint, gp.problem.exploring, result.best_sequence_by_first});
  if (entries_.size() > capacity_) entries_.pop_back();
}

}  // namespace efs::planner
