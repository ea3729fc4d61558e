// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// A CSV line per planning cycle of the exploration planner: where the robot was, which mode and
// hypothesis guided, the guidepoint states under it, the target group, the next guidepoint and
// the FE-TSP's terminal, the goal handed to the local planner, why the cycle ran and what
// became of the previous target, how many surface cells were well observed by then. What a
// person reads to see why a flight went where it went (explore_mission --plan-log).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <ostream>
#include <string>

#include "prior_guided_planner/exploration_manager.h"

namespace efs::mission {

/// The `guidepoints` column: per guidepoint of the active hypothesis, in prior order, its state
/// (U unexplored, E exploring, X explored, O outside) and its number of attached viewpoints,
/// space-separated ("E3 X0 U0"). A guidepoint whose state flips between plans is what turns a
/// flight around; this column shows which one it was.
std::string guidepointsText(const planner::HypothesisAttachment& attachment);

/// How the guidance's first guidepoint changed from one plan to the next, by the MCTS's own
/// numbers: a flight whose next guidepoint flips A-B-A is read from these, a near tie (a gap of
/// a few metres in a sequence of hundreds) against a guidepoint that lost its viewpoints.
struct FirstGuidepointSwitch {
  /// The first guidepoint of the selected sequence (guidepoint index), if a hypothesis guided.
  std::optional<int> first;
  /// Filled only when the first guidepoint differs from `previous_first` under the same
  /// hypothesis: the previous one's state now, and, while it can still come first (a node of
  /// the sequencing problem that the root reaches), how much longer the best sequence starting
  /// there is than the selected one [m] and how much longer its first leg, the mean path from
  /// the robot to its viewpoints [m].
  std::optional<planner::GuidepointState> previous_state;
  std::optional<double> gap_m, first_leg_gap_m;
};
FirstGuidepointSwitch firstGuidepointSwitch(const planner::PlanningResult& plan,
                                            std::optional<int> previous_first,
                                            int previous_hypothesis_id);

class PlanLog {
 public:
  /// Writes the header line.
  explicit PlanLog(std::ostream& out);
  /// One line for the manager's last plan (nothing before the first plan).
  void record(double time_s, const Eigen::Vector3d& robot_world_m,
              const planner::ExplorationManager& manager);
  size_t rows() const { return rows_; }

 private:
  std::ostream& out_;
  size_t rows_ = 0;
  /// The goal viewpoint of the last line, for the `previous_target_rank` column.
  std::optional<int> previous_target_id_;
  /// The first guidepoint of the last line and its hypothesis, for the `first_switch_*` columns.
  std::optional<int> previous_first_;
  int previous_hypothesis_id_ = -1;
};

}  // namespace efs::mission
