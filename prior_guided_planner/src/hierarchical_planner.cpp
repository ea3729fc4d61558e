// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/hierarchical_planner.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "efs_common/config_check.h"

namespace efs::planner {

void HierarchicalPlannerConfig::validate() const {
  attachment.validate();
  sequencing.validate();
  mcts.validate();
  fe_tsp.validate();
  greedy.validate();
  requireInRange("min_confidence", min_confidence, 0.0, 1e9);
  requireInRange("tour_searched_viewpoints", tour_searched_viewpoints, 1, 100000);
  requireInRange("prior_free_max_viewpoints", prior_free_max_viewpoints, 1, 100000);
  requireInRange("keep_first_guidepoint_fraction", keep_first_guidepoint_fraction, 0.0, 1.0);
  requireInRange("leftover_detour_m", leftover_detour_m, 0.0, 1e4);
}

HierarchicalPlanner::HierarchicalPlanner(HierarchicalPlannerConfig config)
    : config_(config), mcts_(config_.mcts) {
  config_.validate();
}

PlanningResult HierarchicalPlanner::plan(const PlanningInput& in) {
  if (!in.path_length_m) throw std::invalid_argument("HierarchicalPlanner: no path length oracle");
  PlanningResult res;
  const int nv = static_cast<int>(in.viewpoints.size());
  if (nv == 0) {
    res.status = PlanningStatus::kNoViewpoints;
    return res;
  }
  std::vector<double> robot_len(nv);
  bool any = false;
  for (int i = 0; i < nv; ++i) {
    robot_len[i] = in.path_length_m(kRobotNode, i);
    if (std::isnan(robot_len[i]))
      throw std::invalid_argument("HierarchicalPlanner: path length to viewpoint " +
                                  std::to_string(i) + " is NaN");
    any = any || robot_len[i] < kUnreachable;
  }
  if (!any) {
    res.status = PlanningStatus::kNoReachableViewpoint;
    for (int i = 0; i < nv; ++i) res.tour.unreachable_viewpoints.push_back(i);
    res.tour.feasible = false;
    return res;
  }

  if (config_.mode == BaselineMode::kNearestFrontier) {
    int best = -1;
    for (int i = 0; i < nv; ++i)
      if (robot_len[i] < kUnreachable && (best < 0 || robot_len[i] < robot_len[best])) best = i;
    res.mode_used = BaselineMode::kNearestFrontier;
    res.tour.viewpoints = {best};
    res.tour.cost_s = robot_len[best] / config_.fe_tsp.v_max_mps;
    for (int i = 0; i < nv; ++i)
      if (!(robot_len[i] < kUnreachable)) res.tour.unreachable_viewpoints.push_back(i);
    return res;
  }

  const auto sortHypotheses = [&] {
    for (size_t j = 0; j < in.hypotheses.size(); ++j) {
      const Hypothesis& h = in.hypotheses[j];
      if (auto why = hypothesisDefect(h)) {
        res.rejected.push_back({h.id, *why});
      } else if (h.confidence < config_.min_confidence) {
        res.rejected.push_back({h.id, "confidence below min_confidence"});
      } else {
        res.used_hypotheses.push_back(static_cast<int>(j));
      }
    }
  };

  if (config_.mode == BaselineMode::kGreedyPrior && in.prior &&
      !in.prior->predicted_free_sketch_m.empty()) {
    in.prior->validate();
    sortHypotheses();
    int best_h = -1;
    for (int j : res.used_hypotheses)
      if (best_h < 0 || in.hypotheses[j].confidence > in.hypotheses[best_h].confidence) best_h = j;
    if (best_h >= 0) {
      const Hypothesis& h = in.hypotheses[best_h];
      const double cell_world_m = h.T_world_sketch.scale * in.prior->predicted_free_cell_m;
      res.greedy =
          scoreGreedyPrior(in.viewpoints, robot_len,
                           unobservedPredictedFree(*in.prior, h, in.observation, config_.greedy),
                           cell_world_m * cell_world_m, config_.greedy);
      if (res.greedy.best >= 0) {
        res.mode_used = BaselineMode::kGreedyPrior;
        res.active_hypothesis_id = h.id;
        res.tour.viewpoints = {res.greedy.best};
        res.tour.cost_s = robot_len[res.greedy.best] / config_.fe_tsp.v_max_mps;
        for (int i = 0; i < nv; ++i)
          if (!(robot_len[i] < kUnreachable)) res.tour.unreachable_viewpoints.push_back(i);
        return res;
      }
    }
  }

  if (config_.mode == BaselineMode::kProposed && in.prior && in.prior->size() > 0) {
    in.prior->validate();
    sortHypotheses();
    for (size_t k = 0; k < res.used_hypotheses.size(); ++k) {
      const Hypothesis& h = in.hypotheses[res.used_hypotheses[k]];
      res.attachments.push_back(attachViewpoints(h, *in.prior, in.viewpoints, in.observation,
                                                 in.bounds_world_m, config_.attachment,
                                                 in.robot.position_world_m.head<2>()));
      HypothesisSequence hs;
      hs.confidence = h.confidence;
      hs.problem = buildGuidepointProblem(res.attachments.back(), *in.prior, h.T_world_sketch.scale,
                                          robot_len, config_.sequencing);
      std::optional<MctsResult> kept;
      if (config_.reuse_sequences) kept = memo_.recall(hs.problem);
      if (kept) {
        hs.mcts = std::move(*kept);
      } else {
        const std::vector<int> warm = warmSequence(h.id, hs.problem);
        hs.mcts = mcts_.solve(hs.problem.problem, config_.mcts.seed + 7919 * k,
                              warm.empty() ? nullptr : &warm);
        if (config_.reuse_sequences) memo_.remember(hs.problem, hs.mcts);
      }
      if (const auto kept = last_first_guidepoint_.find(h.id); kept != last_first_guidepoint_.end())
        creditKeptFirstGuidepoint(hs, kept->second, config_.keep_first_guidepoint_fraction);
      res.sequences.push_back(std::move(hs));
    }
    if (!res.used_hypotheses.empty()) {
      res.groups = groupViewpoints(res.attachments, nv);
      res.selection = selectPriorSequence(res.groups, res.sequences, robot_len);
      rememberSequences(in, res);
      if (res.selection.group >= 0 && res.selection.hypothesis >= 0) {
        const int hk = res.selection.hypothesis;
        // A selected hypothesis always has a sequence: it starts at the target group.
        const std::vector<int>& seq = res.selection.guidepoint_sequence;
        const std::vector<Eigen::Vector2d>& gp = res.attachments[hk].guidepoints_world_m;
        std::optional<Eigen::Vector2d> terminal;
        if (seq.size() >= 2) terminal = gp[seq[1]];
        // Leftovers hang (in hk) on explored guidepoints, so none is isolated or in the target
        // group, whose guidepoint starts hk's sequence: appended, they cannot repeat.
        const std::vector<int> on_the_way = leftoversOnTheWay(
            res.attachments[hk], in.viewpoints, robot_len, in.robot.position_world_m.head<2>(),
            terminal.value_or(gp[seq[0]]), config_.leftover_detour_m);
        res.selection.target_viewpoints.insert(res.selection.target_viewpoints.end(),
                                               on_the_way.begin(), on_the_way.end());
        std::vector<int> members = res.selection.isolated_viewpoints;
        members.insert(members.end(), res.selection.target_viewpoints.begin(),
                       res.selection.target_viewpoints.end());
        res.tour = solveFeTsp(in.robot, in.viewpoints, res.selection.isolated_viewpoints,
                              res.selection.target_viewpoints, terminal,
                              boundedLengths(in, robot_len, std::move(members)), config_.fe_tsp,
                              warmStart());
        res.mode_used = BaselineMode::kProposed;
        res.active_hypothesis_id = in.hypotheses[res.used_hypotheses[hk]].id;
        if (!res.tour.viewpoints.empty()) {
          rememberTour(in, res.tour);
          return res;
        }
      }
    }
  }
  // No prior, no usable hypothesis, no target group (or nothing reachable in it), or nothing
  // predicted unknown in reach (greedy_prior): prior-free.
  res.mode_used = BaselineMode::kPriorFree;
  res.active_hypothesis_id = -1;
  res.tour = priorFreeTour(in, robot_len);
  rememberTour(in, res.tour);
  return res;
}

namespace {
// The guidepoint sequence of hypothesis k in plan `res`. The guiding hypothesis' is the one the
// vehicle was sent along, which with several hypotheses (CalcRisk) need not be its own shortest.
std::vector<int> plannedSequence(const PlanningResult& res, size_t k) {
  if (static_cast<int>(k) == res.selection.hypothesis && !res.selection.guidepoint_sequence.empty())
    return res.selection.guidepoint_sequence;
  return toGuidepoints(res.sequences[k].problem, res.sequences[k].mcts.sequence);
}
}  // namespace

void HierarchicalPlanner::rememberSequences(const PlanningInput& in, const PlanningResult& res) {
  const bool keep_first = config_.keep_first_guidepoint_fraction > 0.0;
  if (!keep_first && !config_.warm_start_sequences) return;
  if (keep_first) last_first_guidepoint_.clear();
  for (size_t k = 0; k < res.sequences.size(); ++k) {
    std::vector<int> seq = plannedSequence(res, k);
    if (seq.empty()) continue;
    const int id = in.hypotheses[res.used_hypotheses[k]].id;
    if (keep_first) last_first_guidepoint_[id] = seq.front();
    if (config_.warm_start_sequences) last_sequence_[id] = std::move(seq);
  }
}

std::vector<int> HierarchicalPlanner::warmSequence(int id, const GuidepointProblem& problem) const {
  const auto it = last_sequence_.find(id);
  if (!config_.warm_start_sequences || it == last_sequence_.end()) return {};
  return toProblemNodes(problem, it->second);
}

const std::vector<int>* HierarchicalPlanner::warmStart() const {
  return config_.warm_start_tours && !last_tour_ids_.empty() ? &last_tour_ids_ : nullptr;
}

void HierarchicalPlanner::rememberTour(const PlanningInput& in, const LocalTour& tour) {
  if (!config_.warm_start_tours) return;
  last_tour_ids_.clear();
  for (int v : tour.viewpoints) last_tour_ids_.push_back(in.viewpoints[v].id);
}

double tourEdgeEstimate_m(const Eigen::Vector3d& a_world_m, double robot_to_a_m,
                          const Eigen::Vector3d& b_world_m, double robot_to_b_m) {
  return std::max((a_world_m - b_world_m).norm(), std::abs(robot_to_a_m - robot_to_b_m));
}

// The tour covers every reachable viewpoint up to prior_free_max_viewpoints, though only the
// nearest tour_searched_viewpoints have searched lengths between them. A tour over the
// searched ones alone does not see the work beyond them, and what it leaves out shifts as the
// robot moves: flying east drops far western viewpoints, the western side looks short and the
// tour turns west, and back. Seen on the paper-size cave: minutes of 2 s flips between targets
// 78 m west and 49 m east, the vehicle within 3 m.
LocalTour HierarchicalPlanner::priorFreeTour(const PlanningInput& in,
                                             const std::vector<double>& robot_len) const {
  const int nv = static_cast<int>(in.viewpoints.size());
  std::vector<int> toured;
  std::vector<int> unreachable;
  for (int i = 0; i < nv; ++i) (robot_len[i] < kUnreachable ? toured : unreachable).push_back(i);
  // Sorted by L(X_r, V) only when some are left unsearched: the ATSP's answer may depend on the
  // order of equal choices.
  if (static_cast<int>(toured.size()) > config_.tour_searched_viewpoints) {
    std::stable_sort(toured.begin(), toured.end(),
                     [&](int a, int b) { return robot_len[a] < robot_len[b]; });
    if (static_cast<int>(toured.size()) > config_.prior_free_max_viewpoints)
      toured.resize(config_.prior_free_max_viewpoints);
  } else if (unreachable.empty()) {
    return solvePriorFreeTour(in.robot, in.viewpoints, in.path_length_m, config_.fe_tsp,
                              warmStart());
  }
  std::vector<PlanViewpoint> sub;
  for (int i : toured) sub.push_back(in.viewpoints[i]);
  const PathLengthFn bounded = boundedLengths(in, robot_len, toured);
  const PathLengthFn sub_len = [&](int a, int b) {
    return bounded(a == kRobotNode ? kRobotNode : toured[a],
                   b == kRobotNode ? kRobotNode : toured[b]);
  };
  LocalTour t = solvePriorFreeTour(in.robot, sub, sub_len, config_.fe_tsp, warmStart());
  for (int& v : t.viewpoints) v = toured[v];
  for (int& v : t.unreachable_viewpoints) v = toured[v];
  t.unreachable_viewpoints.insert(t.unreachable_viewpoints.end(), unreachable.begin(),
                                  unreachable.end());
  std::sort(t.unreachable_viewpoints.begin(), t.unreachable_viewpoints.end());
  return t;
}

PathLengthFn HierarchicalPlanner::boundedLengths(const PlanningInput& in,
                                                 const std::vector<double>& robot_len,
                                                 std::vector<int> members) const {
  const int n_searched = config_.tour_searched_viewpoints;
  if (static_cast<int>(members.size()) <= n_searched) return in.path_length_m;
  std::stable_sort(members.begin(), members.end(),
                   [&](int a, int b) { return robot_len[a] < robot_len[b]; });
  auto searched = std::make_shared<std::vector<bool>>(in.viewpoints.size(), false);
  for (int k = 0; k < n_searched; ++k) (*searched)[static_cast<size_t>(members[k])] = true;
  return [&in, &robot_len, searched](int a, int b) {
    if (a == kRobotNode || b == kRobotNode ||
        ((*searched)[static_cast<size_t>(a)] && (*searched)[static_cast<size_t>(b)]))
      return in.path_length_m(a, b);
    return tourEdgeEstimate_m(in.viewpoints[a].position_world_m, robot_len[a],
                              in.viewpoints[b].position_world_m, robot_len[b]);
  };
}

}  // namespace efs::planner
