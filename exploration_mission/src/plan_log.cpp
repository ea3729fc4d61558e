// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/plan_log.h"

#include "exploration_mission/csv_field.h"

#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace efs::mission {

namespace {
// In the order of planner::GuidepointState (record() counts the states the same way).
constexpr char kLetter[] = "UEXO";
}  // namespace

std::string guidepointsText(const planner::HypothesisAttachment& attachment) {
  std::string text;
  for (size_t j = 0; j < attachment.states.size(); ++j) {
    if (j > 0) text += ' ';
    text += kLetter[static_cast<int>(attachment.states[j])];
    text += std::to_string(j < attachment.attached.size() ? attachment.attached[j].size() : 0);
  }
  return text;
}

FirstGuidepointSwitch firstGuidepointSwitch(const planner::PlanningResult& plan,
                                            std::optional<int> previous_first,
                                            int previous_hypothesis_id) {
  FirstGuidepointSwitch out;
  const int hk = plan.selection.hypothesis;
  if (hk < 0 || static_cast<size_t>(hk) >= plan.sequences.size() ||
      static_cast<size_t>(hk) >= plan.attachments.size() ||
      plan.selection.guidepoint_sequence.empty())
    return out;
  out.first = plan.selection.guidepoint_sequence.front();
  if (!previous_first || *previous_first == *out.first ||
      previous_hypothesis_id != plan.active_hypothesis_id)
    return out;
  const planner::HypothesisAttachment& att = plan.attachments[hk];
  if (*previous_first < 0 || static_cast<size_t>(*previous_first) >= att.states.size()) return out;
  out.previous_state = att.states[*previous_first];
  const planner::HypothesisSequence& hs = plan.sequences[hk];
  const std::vector<int>& nodes = hs.problem.node_guidepoint;
  const auto node = [&](int g) {
    const auto it = std::find(nodes.begin() + 1, nodes.end(), g);
    return it == nodes.end() ? -1 : static_cast<int>(it - nodes.begin());
  };
  const int prev = node(*previous_first), chosen = node(*out.first);
  const std::vector<double>& by_first = hs.mcts.best_length_by_first;
  if (prev < 1 || chosen < 1 || static_cast<size_t>(std::max(prev, chosen)) >= by_first.size() ||
      !hs.problem.problem.exploring[prev] || !(by_first[prev] < planner::kUnreachable) ||
      !(by_first[chosen] < planner::kUnreachable))
    return out;
  out.gap_m = by_first[prev] - by_first[chosen];
  out.first_leg_gap_m = hs.problem.problem.cost(0, prev) - hs.problem.problem.cost(0, chosen);
  return out;
}

PlanLog::PlanLog(std::ostream& out) : out_(out) {
  out_ << "time_s,x_m,y_m,z_m,state,mode,active_hypothesis,hypotheses,viewpoints,unexplored,"
          "exploring,explored,outside,target_group,isolated,next_guidepoint_x_m,"
          "next_guidepoint_y_m,terminal_x_m,terminal_y_m,goal_x_m,goal_y_m,goal_z_m,viewpoint_x_m,"
          "viewpoint_y_m,viewpoint_z_m,tour,guidepoints,replan_reason,target_viewpoint_id,"
          "previous_target_rank,first_guidepoint,previous_first_state,first_switch_gap_m,"
          "first_switch_leg_gap_m,well_observed_cells,message\n";
}

void PlanLog::record(double time_s, const Eigen::Vector3d& robot,
                     const planner::ExplorationManager& manager) {
  const planner::PlanningResult* plan = manager.lastPlan();
  if (!plan) return;
  const planner::ExplorationTarget& target = manager.target();
  std::array<int, 4> states{};  // unexplored, exploring, explored, outside
  const planner::HypothesisAttachment* attachment = manager.activeAttachment();
  if (attachment)
    for (planner::GuidepointState s : attachment->states) ++states[static_cast<int>(s)];
  const std::vector<Eigen::Vector2d> sequence = manager.activeGuidepointSequence();
  const auto xy = [&](size_t i) {
    if (i >= sequence.size()) return std::string(",");
    return std::to_string(sequence[i].x()) + "," + std::to_string(sequence[i].y());
  };
  out_ << time_s << ',' << robot.x() << ',' << robot.y() << ',' << robot.z() << ','
       << planner::toString(target.state) << ',' << planner::toString(plan->mode_used) << ','
       << plan->active_hypothesis_id << ',' << plan->used_hypotheses.size() << ','
       << manager.viewpoints().size() << ',' << states[0] << ',' << states[1] << ',' << states[2]
       << ',' << states[3] << ',' << plan->selection.target_viewpoints.size() << ','
       << plan->selection.isolated_viewpoints.size() << ',' << xy(0) << ',' << xy(1) << ',';
  const auto xyz = [&](const Eigen::Vector3d& p) {
    if (target.has_goal) {
      out_ << p.x() << ',' << p.y() << ',' << p.z();
    } else {
      out_ << ",,";
    }
  };
  xyz(target.goal_world_m);
  out_ << ',';
  xyz(target.viewpoint_world_m);
  out_ << ',' << plan->tour.viewpoints.size() << ','
       << (attachment ? guidepointsText(*attachment) : std::string()) << ','
       << planner::toString(target.replan_reason) << ',';
  if (target.goal_viewpoint_id) out_ << *target.goal_viewpoint_id;
  out_ << ',';
  // Where the previous target went in this tour: 0 it is still first, k it was put behind k
  // others, empty it is no longer in the tour (reached, seen, set aside, or no previous one).
  if (previous_target_id_) {
    const std::vector<planner::PlanViewpoint>& vps = manager.viewpoints();
    const std::vector<int>& tour = plan->tour.viewpoints;
    for (size_t k = 0; k < tour.size(); ++k) {
      const int i = tour[k];
      if (i >= 0 && static_cast<size_t>(i) < vps.size() && vps[i].id == *previous_target_id_) {
        out_ << k;
        break;
      }
    }
  }
  const FirstGuidepointSwitch sw =
      firstGuidepointSwitch(*plan, previous_first_, previous_hypothesis_id_);
  const auto number = [&](const std::optional<double>& v) {
    out_ << ',';
    if (v) out_ << *v;
  };
  out_ << ',';
  if (sw.first) out_ << *sw.first;
  out_ << ',';
  if (sw.previous_state) out_ << kLetter[static_cast<int>(*sw.previous_state)];
  number(sw.gap_m);
  number(sw.first_leg_gap_m);
  out_ << ',' << manager.observationMap().numWellObserved() << ',' << csvQuoted(target.message)
       << '\n';
  previous_target_id_ = target.goal_viewpoint_id;
  previous_first_ = sw.first;
  previous_hypothesis_id_ = plan->active_hypothesis_id;
  ++rows_;
}

}  // namespace efs::mission
