// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// One planning cycle of the paper's Algorithm 2 over abstract inputs: per usable hypothesis
// TransformVps + AttachVps + states + MCTS; GroupVps; CalcRisk (more than one hypothesis) and
// SelectPriSeq; FE-TSP to the second next guidepoint. The baselines (prior_free,
// nearest_frontier, greedy_prior) run in the same call, chosen by `mode`. Falls back to the
// prior-free tour when there is no prior, no usable hypothesis, or no target group; reports "no
// viewpoints" so the caller can terminate the exploration.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "prior_guided_planner/baseline_mode.h"
#include "prior_guided_planner/fe_tsp.h"
#include "prior_guided_planner/greedy_prior.h"
#include "prior_guided_planner/sequence_memo.h"
#include "prior_guided_planner/sequence_selection.h"

namespace efs::planner {

struct HierarchicalPlannerConfig {
  BaselineMode mode = BaselineMode::kProposed;
  AttachmentConfig attachment;
  SequencingConfig sequencing;
  MctsConfig mcts;
  FeTspConfig fe_tsp;
  /// The greedy_prior baseline's information gain and utility.
  GreedyPriorConfig greedy;
  /// Hypotheses with a confidence below this are not used (and reported as rejected).
  double min_confidence = 0.0;
  /// Path lengths between the viewpoints of a tour (prior-free, and the FE-TSP's isolated and
  /// target viewpoints) are searched among this many of them, the nearest by L(X_r, V): it
  /// bounds the O(N^2) searches. An edge with a farther viewpoint is estimated
  /// (tourEdgeEstimate_m) instead of left out. Unbounded, a paper-size garage's FE-TSP over a
  /// few hundred viewpoints (sparse guidepoints, large groups) spent half the process in them.
  int tour_searched_viewpoints = 40;
  /// The prior-free tour covers at most this many viewpoints, the nearest by L(X_r, V): it
  /// bounds the ATSP. Beyond it, what the tour cannot see may bias its direction (see
  /// priorFreeTour in hierarchical_planner.cpp).
  int prior_free_max_viewpoints = 300;
  /// Reuse a hypothesis' guidepoint sequences while its guidepoints and their states are
  /// unchanged (sequence_memo.h); false solves the MCTS in every plan.
  bool reuse_sequences = true;
  /// Start each tour's solver from the last plan's tour order (its viewpoints still present,
  /// in that order, new ones after), so that only a tour at most as costly replaces it. A
  /// periodic re-solve of a 300-viewpoint prior-free tour found another local optimum and
  /// turned the whole tour round (README, "Why each plan ran"). Off by default until measured
  /// beyond one paper-garage prior-free flight (59.2 -> 67.3 % at 600 s, planner CPU +33 %).
  bool warm_start_tours = false;
  /// Start each hypothesis' MCTS from its last plan's guidepoint sequence (what is left of it,
  /// new guidepoints inserted where cheapest) instead of the assignment relaxation, so that a
  /// re-solve keeps the old order unless its search finds a shorter one. Over the 445
  /// guidepoints of the Pittsburgh mine the first guidepoint changed in 951 of 4 307 guided
  /// plans, by a median 8.7 m in sequences of kilometres: different local optima of each
  /// fresh solve, and the vehicle turned with them.
  bool warm_start_sequences = false;
  /// The last plan's first guidepoint stays first while the best sequence starting there is at
  /// most this fraction of the best sequence's length longer (creditKeptFirstGuidepoint). In the
  /// paper garage the next guidepoint changed 31 times in 200 s, 21 of them from one still
  /// exploring whose sequence the MCTS found a median 13 m longer in about a kilometre: a near
  /// tie, while the vehicle turned between groups 30 m apart. 0: the paper's choice.
  double keep_first_guidepoint_fraction = 0.0;
  /// With the seen rule on, the guided tour also takes the leftovers of seen guidepoints whose
  /// visit lengthens the way to the FE-TSP's terminal (the guidepoint after the target group;
  /// the target group's own when the sequence has one guidepoint) by at most this much
  /// (leftoversOnTheWay). 0: they wait for the prior-free tour at the end [m].
  double leftover_detour_m = 0.0;
  /// Throws efs::ConfigError naming the key.
  void validate() const;
};

struct PlanningInput {
  RobotPose robot;
  std::vector<PlanViewpoint> viewpoints;
  PathLengthFn path_length_m;
  std::vector<Hypothesis> hypotheses;
  /// May be null (no prior: prior-free).
  const GuidepointPrior* prior = nullptr;
  ObservationQuery observation;
  std::optional<Eigen::AlignedBox2d> bounds_world_m;
};

enum class PlanningStatus {
  kOk,
  kNoViewpoints,          ///< nothing left to explore: the caller terminates
  kNoReachableViewpoint,  ///< viewpoints exist but the robot reaches none of them
};

struct RejectedHypothesis {
  int id = 0;
  std::string reason;
};

struct PlanningResult {
  PlanningStatus status = PlanningStatus::kOk;
  /// kProposed / kGreedyPrior when the prior guided this cycle, kPriorFree when it fell back,
  /// kNearestFrontier in that mode.
  BaselineMode mode_used = BaselineMode::kPriorFree;
  LocalTour tour;
  /// Hypotheses used (indices into the input) with their attachments and sequences.
  std::vector<int> used_hypotheses;
  std::vector<HypothesisAttachment> attachments;
  std::vector<HypothesisSequence> sequences;
  std::vector<ViewpointGroup> groups;
  PriorSelection selection;
  std::vector<RejectedHypothesis> rejected;
  /// The selected hypothesis' id (-1 when none guided).
  int active_hypothesis_id = -1;
  /// greedy_prior only: per-viewpoint scores (empty in the other modes or without a prior).
  GreedyPriorScores greedy;
};

/// An estimate of L(a, b) for tour edges that are not searched: the larger of two
/// lower bounds, the straight distance and the triangle inequality through the robot,
/// |L(X_r, a) - L(X_r, b)|. The second is exact between points of one passage leading away from
/// the robot, which is where a cave's far viewpoints lie; it is what makes the tour's first
/// step weigh the work beyond the searched ones.
double tourEdgeEstimate_m(const Eigen::Vector3d& a_world_m, double robot_to_a_m,
                          const Eigen::Vector3d& b_world_m, double robot_to_b_m);

class HierarchicalPlanner {
 public:
  explicit HierarchicalPlanner(HierarchicalPlannerConfig config = {});
  /// Throws std::invalid_argument on malformed input (prior sizes, missing oracle). Not const:
  /// the sequences of this plan are remembered for the next (HierarchicalPlannerConfig::
  /// reuse_sequences).
  PlanningResult plan(const PlanningInput& input);
  /// Plans whose MCTS was reused / solved.
  const SequenceMemo& sequenceMemo() const { return memo_; }
  const HierarchicalPlannerConfig& config() const { return config_; }

 private:
  LocalTour priorFreeTour(const PlanningInput& in, const std::vector<double>& robot_len) const;
  /// The warm start for this plan's tour (nullptr when off or there is none).
  const std::vector<int>* warmStart() const;
  void rememberTour(const PlanningInput& in, const LocalTour& tour);
  /// Keeps each hypothesis' first guidepoint of this plan (keep_first_guidepoint_fraction) and
  /// its guidepoint sequence (warm_start_sequences).
  void rememberSequences(const PlanningInput& in, const PlanningResult& res);
  /// The warm start of hypothesis `id`'s MCTS in the problem's node numbers (empty: none).
  std::vector<int> warmSequence(int id, const GuidepointProblem& problem) const;
  /// in.path_length_m searched only between the tour_searched_viewpoints of `members` nearest
  /// to the robot (and from the robot); tourEdgeEstimate_m for every other pair.
  PathLengthFn boundedLengths(const PlanningInput& in, const std::vector<double>& robot_len,
                              std::vector<int> members) const;

  HierarchicalPlannerConfig config_;
  /// Kept between plans so that its rollout workers are too.
  MctsSequencer mcts_;
  SequenceMemo memo_;
  /// Viewpoint ids of the last plan's tour, in order (warm_start_tours).
  std::vector<int> last_tour_ids_;
  /// Per hypothesis id, the first guidepoint of its sequence in the last plan that had one
  /// (keep_first_guidepoint_fraction; empty when that is 0).
  std::map<int, int> last_first_guidepoint_;
  /// Per hypothesis id, its guidepoint sequence (guidepoint indices) in the last plan that
  /// had one (warm_start_sequences).
  std::map<int, std::vector<int>> last_sequence_;
};

}  // namespace efs::planner
