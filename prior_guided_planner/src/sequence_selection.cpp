// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/sequence_selection.h"

#include <algorithm>
#include <map>
#include <stdexcept>

#include "efs_common/config_check.h"

namespace efs::planner {

void SequencingConfig::validate() const {
  requireInRange("sequencing.unconnected_penalty", unconnected_penalty, 1.0, 1e6);
}

GuidepointProblem buildGuidepointProblem(const HypothesisAttachment& att,
                                         const GuidepointPrior& prior, double scale,
                                         const std::vector<double>& robot_to_viewpoint_m,
                                         const SequencingConfig& config) {
  config.validate();
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw std::invalid_argument("buildGuidepointProblem: scale must be finite and > 0");
  if (robot_to_viewpoint_m.size() != att.attached_to.size())
    throw std::invalid_argument(
        "buildGuidepointProblem: " + std::to_string(robot_to_viewpoint_m.size()) +
        " robot path lengths for " + std::to_string(att.attached_to.size()) + " viewpoints");
  GuidepointProblem out;
  out.node_guidepoint.push_back(-1);
  for (int j = 0; j < prior.size(); ++j)
    if (att.states[j] == GuidepointState::kExploring ||
        att.states[j] == GuidepointState::kUnexplored)
      out.node_guidepoint.push_back(j);
  const int m = static_cast<int>(out.node_guidepoint.size());
  MctsProblem& p = out.problem;
  p.cost = CostMatrix(m, 0.0);
  p.exploring.assign(m, false);
  for (int a = 1; a < m; ++a) {
    const int ga = out.node_guidepoint[a];
    if (att.states[ga] == GuidepointState::kExploring) {
      p.exploring[a] = true;
      double sum = 0.0;
      int k = 0;
      for (int v : att.attached[ga])
        if (robot_to_viewpoint_m[v] < kUnreachable) sum += robot_to_viewpoint_m[v], ++k;
      p.cost(0, a) = k > 0 ? sum / k : kUnreachable;
    } else {
      p.cost(0, a) = kUnreachable;
    }
    for (int b = 1; b < m; ++b) {
      if (a == b) continue;
      const int gb = out.node_guidepoint[b];
      const double prm = prior.prm_distance_m(ga, gb);
      p.cost(a, b) = prm < kUnreachable
                         ? scale * prm
                         : scale * config.unconnected_penalty *
                               (prior.positions_sketch_m[ga] - prior.positions_sketch_m[gb]).norm();
    }
  }
  return out;
}

void creditKeptFirstGuidepoint(HypothesisSequence& hs, int kept, double fraction) {
  MctsResult& r = hs.mcts;
  const std::vector<int>& nodes = hs.problem.node_guidepoint;
  const auto it = std::find(nodes.begin() + std::min<size_t>(1, nodes.size()), nodes.end(), kept);
  if (!(fraction > 0.0) || it == nodes.end() || !(r.length < kUnreachable)) return;
  const size_t node = static_cast<size_t>(it - nodes.begin());
  if (node >= r.best_length_by_first.size() || node >= r.best_sequence_by_first.size() ||
      !hs.problem.problem.exploring[node] || !(r.best_length_by_first[node] < kUnreachable) ||
      r.best_sequence_by_first[node].empty())
    return;
  r.best_length_by_first[node] -= fraction * r.length;
  if (r.best_length_by_first[node] < r.length) {
    r.length = r.best_length_by_first[node];
    r.sequence = r.best_sequence_by_first[node];
  }
}

std::vector<int> leftoversOnTheWay(const HypothesisAttachment& attachment,
                                   const std::vector<PlanViewpoint>& viewpoints,
                                   const std::vector<double>& robot_to_viewpoint_m,
                                   const Eigen::Vector2d& robot_xy_world_m,
                                   const Eigen::Vector2d& toward_xy_world_m, double max_detour_m) {
  const size_t n = attachment.attached_to.size();
  if (viewpoints.size() != n || robot_to_viewpoint_m.size() != n)
    throw std::invalid_argument("leftoversOnTheWay: " + std::to_string(viewpoints.size()) +
                                " viewpoints and " + std::to_string(robot_to_viewpoint_m.size()) +
                                " robot path lengths for an attachment of " + std::to_string(n));
  std::vector<int> out;
  if (!(max_detour_m > 0.0)) return out;
  const double direct_m = (toward_xy_world_m - robot_xy_world_m).norm();
  for (size_t i = 0; i < n; ++i) {
    const int g = attachment.attached_to[i];
    if (g < 0 || static_cast<size_t>(g) >= attachment.states.size() ||
        attachment.states[g] != GuidepointState::kExplored ||
        !(robot_to_viewpoint_m[i] < kUnreachable))
      continue;
    const double via_m = robot_to_viewpoint_m[i] +
                         (toward_xy_world_m - viewpoints[i].position_world_m.head<2>()).norm();
    if (via_m - direct_m <= max_detour_m) out.push_back(static_cast<int>(i));
  }
  return out;
}

bool ViewpointGroup::isolated() const {
  return std::all_of(key.begin(), key.end(), [](int g) { return g < 0; });
}

std::vector<ViewpointGroup> groupViewpoints(const std::vector<HypothesisAttachment>& attachments,
                                            int num_viewpoints) {
  std::map<std::vector<int>, int> index;
  std::vector<ViewpointGroup> groups;
  for (int i = 0; i < num_viewpoints; ++i) {
    std::vector<int> key;
    for (const auto& a : attachments) {
      if (static_cast<int>(a.attached_to.size()) != num_viewpoints)
        throw std::invalid_argument("groupViewpoints: attachment of the wrong size");
      key.push_back(a.attached_to[i]);
    }
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, static_cast<int>(groups.size())).first;
      groups.push_back(ViewpointGroup{key, {}});
    }
    groups[it->second].viewpoints.push_back(i);
  }
  return groups;
}

namespace {

int problemNode(const GuidepointProblem& p, int guidepoint) {
  for (size_t k = 1; k < p.node_guidepoint.size(); ++k)
    if (p.node_guidepoint[k] == guidepoint) return static_cast<int>(k);
  return -1;
}

double meanRobotLength(const ViewpointGroup& g, const std::vector<double>& l) {
  double s = 0.0;
  int k = 0;
  for (int v : g.viewpoints)
    if (l[v] < kUnreachable) s += l[v], ++k;
  return k ? s / k : kUnreachable;
}

}  // namespace

std::vector<int> toGuidepoints(const GuidepointProblem& p, const std::vector<int>& nodes) {
  std::vector<int> out;
  for (int k : nodes) out.push_back(p.node_guidepoint[k]);
  return out;
}

std::vector<int> toProblemNodes(const GuidepointProblem& p, const std::vector<int>& guidepoints) {
  int max_g = -1;
  for (int g : p.node_guidepoint) max_g = std::max(max_g, g);
  std::vector<int> node_of(static_cast<size_t>(max_g + 1), -1);
  for (size_t k = 1; k < p.node_guidepoint.size(); ++k)
    if (p.node_guidepoint[k] >= 0)
      node_of[static_cast<size_t>(p.node_guidepoint[k])] = static_cast<int>(k);
  std::vector<int> out;
  for (int g : guidepoints)
    if (g >= 0 && g <= max_g && node_of[static_cast<size_t>(g)] > 0)
      out.push_back(node_of[static_cast<size_t>(g)]);
  return out;
}

std::vector<double> calcRisk(const std::vector<ViewpointGroup>& groups,
                             const std::vector<HypothesisSequence>& sequences,
                             const std::vector<double>& robot_to_viewpoint_m) {
  std::vector<double> risk(groups.size(), 0.0);
  for (size_t i = 0; i < groups.size(); ++i) {
    if (groups[i].isolated()) {
      risk[i] = kUnreachable;
      continue;
    }
    for (size_t j = 0; j < sequences.size(); ++j) {
      const HypothesisSequence& hs = sequences[j];
      const int g = groups[i].key.at(j);
      const int node = g >= 0 ? problemNode(hs.problem, g) : -1;
      double extra;
      if (node > 0 && hs.mcts.best_length_by_first.size() > static_cast<size_t>(node) &&
          hs.mcts.best_length_by_first[node] < kUnreachable && hs.mcts.length < kUnreachable) {
        extra = hs.mcts.best_length_by_first[node] - hs.mcts.length;
      } else {
        extra = 2.0 * meanRobotLength(groups[i], robot_to_viewpoint_m);
      }
      risk[i] += hs.confidence * extra;
    }
  }
  return risk;
}

PriorSelection selectPriorSequence(const std::vector<ViewpointGroup>& groups,
                                   const std::vector<HypothesisSequence>& sequences,
                                   const std::vector<double>& robot_to_viewpoint_m) {
  PriorSelection sel;
  for (const auto& g : groups)
    if (g.isolated())
      sel.isolated_viewpoints.insert(sel.isolated_viewpoints.end(), g.viewpoints.begin(),
                                     g.viewpoints.end());
  std::sort(sel.isolated_viewpoints.begin(), sel.isolated_viewpoints.end());
  if (sequences.empty()) return sel;

  if (sequences.size() == 1) {
    const HypothesisSequence& hs = sequences[0];
    if (!hs.mcts.feasible || hs.mcts.sequence.empty()) return sel;
    const int g0 = hs.problem.node_guidepoint[hs.mcts.sequence.front()];
    for (size_t i = 0; i < groups.size(); ++i)
      if (groups[i].key.at(0) == g0) sel.group = static_cast<int>(i);
    sel.hypothesis = 0;
    sel.guidepoint_sequence = toGuidepoints(hs.problem, hs.mcts.sequence);
    if (sel.group >= 0) sel.target_viewpoints = groups[sel.group].viewpoints;
    return sel;
  }

  sel.risk = calcRisk(groups, sequences, robot_to_viewpoint_m);
  // The confidence of the best hypothesis attaching each group, for ties.
  auto bestConf = [&](size_t i) {
    double c = -1.0;
    for (size_t j = 0; j < sequences.size(); ++j)
      if (groups[i].key[j] >= 0) c = std::max(c, sequences[j].confidence);
    return c;
  };
  for (size_t i = 0; i < groups.size(); ++i) {
    if (!(sel.risk[i] < kUnreachable)) continue;
    if (sel.group < 0) {
      sel.group = static_cast<int>(i);
      continue;
    }
    const double r = sel.risk[i], rb = sel.risk[sel.group];
    const double tol = 1e-9 * (1.0 + std::abs(rb));
    if (r < rb - tol || (std::abs(r - rb) <= tol && bestConf(i) > bestConf(sel.group)))
      sel.group = static_cast<int>(i);
  }
  if (sel.group < 0) return sel;
  sel.target_viewpoints = groups[sel.group].viewpoints;
  // Among hypotheses attaching the group: prefer those whose best sequence starts there, then
  // the highest confidence.
  int best = -1;
  bool best_points = false;
  for (size_t j = 0; j < sequences.size(); ++j) {
    const int g = groups[sel.group].key[j];
    if (g < 0) continue;
    const HypothesisSequence& hs = sequences[j];
    const int node = problemNode(hs.problem, g);
    if (node <= 0 || hs.mcts.best_sequence_by_first.size() <= static_cast<size_t>(node) ||
        hs.mcts.best_sequence_by_first[node].empty())
      continue;
    const bool points = !hs.mcts.sequence.empty() && hs.mcts.sequence.front() == node;
    if (best < 0 || (points && !best_points) ||
        (points == best_points && hs.confidence > sequences[best].confidence)) {
      best = static_cast<int>(j);
      best_points = points;
    }
  }
  if (best >= 0) {
    const HypothesisSequence& hs = sequences[best];
    sel.hypothesis = best;
    sel.guidepoint_sequence = toGuidepoints(
        hs.problem,
        hs.mcts.best_sequence_by_first[problemNode(hs.problem, groups[sel.group].key[best])]);
  }
  return sel;
}

}  // namespace efs::planner
