// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// From attachments to the MCTS problem of one hypothesis (Sec. VI-B costs), and the prior
// sequence selection across hypotheses (Sec. VI-C): GroupVps, CalcRisk, SelectPriSeq.
#pragma once

#include <vector>

#include "prior_guided_planner/mcts_sequencer.h"
#include "prior_guided_planner/viewpoint_attachment.h"

namespace efs::planner {

struct SequencingConfig {
  /// A guidepoint pair the sketch's PRM does not connect still gets a finite cost:
  /// scale * straight sketch distance * this factor (the sketch may be wrong about
  /// connectivity; the planner should still prefer the connected route).
  double unconnected_penalty = 3.0;
  void validate() const;
};

/// The MCTS problem of one hypothesis and the map from problem nodes to guidepoints.
struct GuidepointProblem {
  MctsProblem problem;
  /// node_guidepoint[k] = guidepoint index of problem node k (k >= 1); [0] = -1 (robot).
  std::vector<int> node_guidepoint;
};

/// Costs of the paper: robot -> exploring guidepoint = mean L(X_r, V) over its attached
/// viewpoints (unreachable viewpoints left out; none reachable -> kUnreachable); guidepoint ->
/// guidepoint = scale * PRM distance; anything -> robot = 0. Nodes are the exploring and
/// unexplored guidepoints. `robot_to_viewpoint_m[i]` = L(X_r, V_i).
GuidepointProblem buildGuidepointProblem(const HypothesisAttachment& attachment,
                                         const GuidepointPrior& prior, double scale,
                                         const std::vector<double>& robot_to_viewpoint_m,
                                         const SequencingConfig& config);

/// Problem nodes (k >= 1) of `p` as guidepoint indices.
std::vector<int> toGuidepoints(const GuidepointProblem& p, const std::vector<int>& nodes);
/// Guidepoint indices as problem nodes of `p`, in order; those that are no node of it are left out.
std::vector<int> toProblemNodes(const GuidepointProblem& p, const std::vector<int>& guidepoints);

/// One hypothesis' MCTS outcome as the selection step needs it.
struct HypothesisSequence {
  double confidence = 1.0;
  GuidepointProblem problem;
  MctsResult mcts;
};

/// Credits the best sequence starting at guidepoint `kept` (the last plan's first guidepoint)
/// with `fraction` of the best sequence's length: its best_length_by_first is lowered by that
/// much and, if it is then the shortest, it becomes the result's sequence and length. Nothing
/// changes when `kept` is not a node the root expands to (no longer exploring, or gone) or has
/// no sequence. The MCTS prices guidepoints as points, so leaving a group half toured for
/// another whose sequence is a metre or two shorter costs what its numbers never see: the
/// vehicle turns, and comes back for the rest. Lengths stay credited for CalcRisk, which then
/// compares the kept group with the same margin.
void creditKeptFirstGuidepoint(HypothesisSequence& sequence, int kept, double fraction);

/// Viewpoints sharing exactly the same attachments under all hypotheses (key[j] = guidepoint
/// index under hypothesis j, or -1).
struct ViewpointGroup {
  std::vector<int> key;
  std::vector<int> viewpoints;
  bool isolated() const;
};

/// GroupVps. Groups are ordered by their first viewpoint index (deterministic).
std::vector<ViewpointGroup> groupViewpoints(const std::vector<HypothesisAttachment>& attachments,
                                            int num_viewpoints);

/// CalcRisk: C(i) = sum_j Conf_j * (L_i^j - L^{j,*}). L_i^j is the best MCTS rollout length that
/// starts at the group's guidepoint under hypothesis j. When the group has no guidepoint under j
/// (or that guidepoint has no rollout), its extra length is the detour to the group and back:
/// 2 * mean L(X_r, V) over its viewpoints. Isolated groups get +inf (they are never the target).
std::vector<double> calcRisk(const std::vector<ViewpointGroup>& groups,
                             const std::vector<HypothesisSequence>& sequences,
                             const std::vector<double>& robot_to_viewpoint_m);

struct PriorSelection {
  int group = -1;       ///< target group index; -1 if there is none
  int hypothesis = -1;  ///< hypothesis whose sequence guides; -1 if none
  /// Guidepoint indices (not problem nodes) of the selected prior sequence.
  std::vector<int> guidepoint_sequence;
  std::vector<int> isolated_viewpoints, target_viewpoints;
  std::vector<double> risk;  ///< per group; empty when the risk step was bypassed
};

/// Leftovers worth taking on the way: viewpoints attached to a guidepoint that the seen rule
/// counted explored (AttachmentConfig::seen_fraction; under the paper's states an explored
/// guidepoint has none) whose visit lengthens the way from the robot to `toward_xy_world_m`
/// by at most `max_detour_m`: L(X_r, V) + |V - toward| - |X_r - toward|, horizontally.
/// Left alone, they wait for the prior-free tour after the last guidepoint, and that tour
/// flies back for them (README, "Guidepoints explored by what was seen"). Sorted, unique.
/// `viewpoints` and `robot_to_viewpoint_m` must match the attachment, else std::invalid_argument.
std::vector<int> leftoversOnTheWay(const HypothesisAttachment& attachment,
                                   const std::vector<PlanViewpoint>& viewpoints,
                                   const std::vector<double>& robot_to_viewpoint_m,
                                   const Eigen::Vector2d& robot_xy_world_m,
                                   const Eigen::Vector2d& toward_xy_world_m, double max_detour_m);

/// SelectPriSeq. With more than one hypothesis: the group of minimum risk (ties to the group
/// whose attaching hypothesis has the highest confidence), then among the hypotheses attaching
/// it the one of highest confidence, with its best sequence starting at that group. With one
/// hypothesis the risk step is bypassed: the target group is the one attached to the first
/// guidepoint of its best sequence.
PriorSelection selectPriorSequence(const std::vector<ViewpointGroup>& groups,
                                   const std::vector<HypothesisSequence>& sequences,
                                   const std::vector<double>& robot_to_viewpoint_m);

}  // namespace efs::planner
