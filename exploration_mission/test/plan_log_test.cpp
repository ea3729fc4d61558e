// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/plan_log.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace efs::mission {
namespace {

/// A scan from `o` of the inside of the box [lo, hi]: each ray of a Fibonacci sphere ends on the
/// first wall it meets.
std::vector<Eigen::Vector3f> boxScan(const Eigen::Vector3d& o, const Eigen::Vector3d& lo,
                                     const Eigen::Vector3d& hi) {
  std::vector<Eigen::Vector3f> pts;
  const int n = 6000;
  for (int i = 0; i < n; ++i) {
    const double z = -1.0 + 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z), az = 2.399963 * i;
    const Eigen::Vector3d d(r * std::cos(az), r * std::sin(az), z);
    double t = 1e9;
    for (int a = 0; a < 3; ++a)
      if (std::abs(d[a]) > 1e-9) t = std::min(t, ((d[a] > 0 ? hi[a] : lo[a]) - o[a]) / d[a]);
    pts.push_back((o + t * d).cast<float>());
  }
  return pts;
}

/// The fields of a CSV line; a quoted field (the message) may hold commas and doubled quotes.
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char ch = line[i];
    if (quoted && ch == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      out.back() += '"';
      ++i;
    } else if (ch == '"') {
      quoted = !quoted;
    } else if (ch == ',' && !quoted) {
      out.emplace_back();
    } else {
      out.back() += ch;
    }
  }
  return out;
}

size_t columns(const std::string& line) { return fields(line).size(); }

/// The value of column `name` of `row` under `header`; fails the test when there is none.
std::string column(const std::string& header, const std::string& row, const std::string& name) {
  const std::vector<std::string> h = fields(header), r = fields(row);
  const auto it = std::find(h.begin(), h.end(), name);
  EXPECT_NE(it, h.end()) << "no column " << name;
  EXPECT_EQ(h.size(), r.size());
  const size_t k = static_cast<size_t>(it - h.begin());
  return it == h.end() || k >= r.size() ? std::string("<missing>") : r[k];
}

TEST(PlanLog, OneLinePerPlanWithTheHeadersColumns) {
  std::ostringstream out;
  PlanLog log(out);
  planner::ExplorationManager m(planner::ExplorationManagerConfig{}, std::nullopt);
  const Eigen::Vector3d robot(2.0, 0.1, 1.6);
  planner::RobotPose pose;
  pose.position_world_m = robot;
  log.record(0.0, robot, m);  // no plan yet: nothing written
  EXPECT_EQ(log.rows(), 0u);
  // A corridor whose far end lies beyond the LiDAR's range: frontiers, so a plan with a goal.
  m.insertScan(robot, boxScan(robot, {0.15, -2.85, 0.15}, {60.0, 3.15, 3.15}));
  const planner::ExplorationTarget& t = m.update(0.1, pose);
  ASSERT_TRUE(t.replanned);
  ASSERT_TRUE(t.has_goal) << t.message;
  log.record(0.1, robot, m);
  EXPECT_EQ(log.rows(), 1u);
  std::istringstream in(out.str());
  std::string header, row, extra;
  ASSERT_TRUE(std::getline(in, header));
  ASSERT_TRUE(std::getline(in, row));
  EXPECT_FALSE(std::getline(in, extra));
  EXPECT_EQ(columns(row), columns(header));
  EXPECT_EQ(header.rfind("time_s,x_m,y_m,z_m,state,mode,", 0), 0u);
  EXPECT_EQ(row.rfind("0.1,2,0.1,1.6,exploring,prior_free,-1,0,", 0), 0u) << row;
  // No hypothesis guided: the guidepoints column is empty.
  EXPECT_EQ(column(header, row, "guidepoints"), "");
  EXPECT_EQ(column(header, row, "replan_reason"), "first_plan");
  EXPECT_EQ(column(header, row, "target_viewpoint_id"), std::to_string(*t.goal_viewpoint_id));
  EXPECT_EQ(column(header, row, "previous_target_rank"), "");  // there was no previous target
  EXPECT_EQ(column(header, row, "first_guidepoint"), "");      // no guidance
  EXPECT_EQ(column(header, row, "first_switch_gap_m"), "");
  // What the plan said, whole, though it holds commas.
  EXPECT_EQ(column(header, row, "message"), t.message);
  EXPECT_NE(t.message.find(','), std::string::npos) << t.message;
  // How much surface the map had seen well by then: what a stalled end of a flight is read from.
  EXPECT_EQ(column(header, row, "well_observed_cells"),
            std::to_string(m.observationMap().numWellObserved()));
  EXPECT_GT(m.observationMap().numWellObserved(), 0u);
}

TEST(PlanLog, SaysWhyEachPlanRanAndWhereThePreviousTargetWent) {
  std::ostringstream out;
  PlanLog log(out);
  planner::ExplorationManagerConfig config;
  config.replan_period_s = 1.0;
  planner::ExplorationManager m(config, std::nullopt);
  const Eigen::Vector3d robot(2.0, 0.1, 1.6);
  planner::RobotPose pose;
  pose.position_world_m = robot;
  m.insertScan(robot, boxScan(robot, {0.15, -2.85, 0.15}, {60.0, 3.15, 3.15}));
  const planner::ExplorationTarget& t = m.update(0.1, pose);
  ASSERT_TRUE(t.has_goal) << t.message;
  log.record(0.1, robot, m);
  const int first_target = *t.goal_viewpoint_id;
  // Before the period is up, with the target standing, nothing is planned.
  EXPECT_FALSE(m.update(0.5, pose).replanned);
  // The period elapsed, nothing seen since: the same target stays first in the new tour.
  ASSERT_TRUE(m.update(1.2, pose).replanned);
  log.record(1.2, robot, m);
  // The vehicle stands at the target viewpoint: reached, so it leaves the tour.
  planner::RobotPose at_target;
  at_target.position_world_m = t.viewpoint_world_m;
  ASSERT_TRUE(m.update(1.3, at_target).replanned);
  log.record(1.3, t.viewpoint_world_m, m);

  std::istringstream in(out.str());
  std::string header, first, periodic, reached;
  ASSERT_TRUE(std::getline(in, header));
  ASSERT_TRUE(std::getline(in, first));
  ASSERT_TRUE(std::getline(in, periodic));
  ASSERT_TRUE(std::getline(in, reached));
  EXPECT_EQ(column(header, periodic, "replan_reason"), "period");
  EXPECT_EQ(column(header, periodic, "target_viewpoint_id"), std::to_string(first_target));
  EXPECT_EQ(column(header, periodic, "previous_target_rank"), "0");
  EXPECT_EQ(column(header, reached, "replan_reason"), "target_reached");
  EXPECT_NE(column(header, reached, "target_viewpoint_id"), std::to_string(first_target));
  EXPECT_EQ(column(header, reached, "previous_target_rank"), "");
}

TEST(PlanLog, GuidepointsColumnGivesEachStateAndItsAttachedViewpoints) {
  planner::HypothesisAttachment a;
  a.states = {planner::GuidepointState::kExploring, planner::GuidepointState::kExplored,
              planner::GuidepointState::kUnexplored, planner::GuidepointState::kOutside};
  a.attached = {{0, 4, 7}, {}, {}, {}};
  EXPECT_EQ(guidepointsText(a), "E3 X0 U0 O0");
  EXPECT_EQ(guidepointsText(planner::HypothesisAttachment{}), "");
}

// One hypothesis (id 11) over guidepoints 0-7: 3 and 5 exploring, 7 unexplored, 6 explored. The
// sequence selected starts at 3; starting at 5 the MCTS found one 4 m longer.
planner::PlanningResult guidedPlan() {
  using planner::GuidepointState;
  planner::PlanningResult plan;
  plan.active_hypothesis_id = 11;
  plan.used_hypotheses = {0};
  planner::HypothesisAttachment att;
  att.states.assign(8, GuidepointState::kUnexplored);
  att.states[3] = att.states[5] = GuidepointState::kExploring;
  att.states[6] = GuidepointState::kExplored;
  plan.attachments = {att};
  planner::HypothesisSequence hs;
  hs.problem.node_guidepoint = {-1, 3, 5, 7};
  hs.problem.problem.cost = planner::CostMatrix(4, 0.0);
  hs.problem.problem.cost(0, 1) = 10.0;
  hs.problem.problem.cost(0, 2) = 13.5;
  hs.problem.problem.exploring = {false, true, true, false};
  hs.mcts.best_length_by_first = {planner::kUnreachable, 100.0, 104.0, planner::kUnreachable};
  hs.mcts.sequence = {1, 2, 3};
  hs.mcts.length = 100.0;
  plan.sequences = {hs};
  plan.selection.hypothesis = 0;
  plan.selection.guidepoint_sequence = {3, 5, 7};
  return plan;
}

TEST(PlanLog, FirstGuidepointSwitchWeighsTheOneLeftAgainstTheOneTaken) {
  const planner::PlanningResult plan = guidedPlan();
  // No previous line, or the same first guidepoint: no switch.
  for (std::optional<int> previous : {std::optional<int>(), std::optional<int>(3)}) {
    const FirstGuidepointSwitch sw = firstGuidepointSwitch(plan, previous, 11);
    ASSERT_TRUE(sw.first);
    EXPECT_EQ(*sw.first, 3);
    EXPECT_FALSE(sw.previous_state);
    EXPECT_FALSE(sw.gap_m);
  }
  // From 5, still exploring: the MCTS found the sequence from 5 4 m longer, 3.5 m of it in the
  // first leg.
  const FirstGuidepointSwitch near_tie = firstGuidepointSwitch(plan, 5, 11);
  ASSERT_TRUE(near_tie.previous_state);
  EXPECT_EQ(*near_tie.previous_state, planner::GuidepointState::kExploring);
  ASSERT_TRUE(near_tie.gap_m && near_tie.first_leg_gap_m);
  EXPECT_DOUBLE_EQ(*near_tie.gap_m, 4.0);
  EXPECT_DOUBLE_EQ(*near_tie.first_leg_gap_m, 3.5);
  // Under another hypothesis the indices mean other places: nothing is compared.
  const FirstGuidepointSwitch other = firstGuidepointSwitch(plan, 5, 12);
  EXPECT_FALSE(other.previous_state);
  EXPECT_FALSE(other.gap_m);
  // A previous first that can no longer come first (unexplored: no viewpoint of its own; or
  // explored, out of the problem): its state, and no gap.
  const FirstGuidepointSwitch unexplored = firstGuidepointSwitch(plan, 7, 11);
  ASSERT_TRUE(unexplored.previous_state);
  EXPECT_EQ(*unexplored.previous_state, planner::GuidepointState::kUnexplored);
  EXPECT_FALSE(unexplored.gap_m);
  const FirstGuidepointSwitch explored = firstGuidepointSwitch(plan, 6, 11);
  ASSERT_TRUE(explored.previous_state);
  EXPECT_EQ(*explored.previous_state, planner::GuidepointState::kExplored);
  EXPECT_FALSE(explored.first_leg_gap_m);
  // No hypothesis guided: no first guidepoint.
  EXPECT_FALSE(firstGuidepointSwitch(planner::PlanningResult{}, 5, -1).first);
}

}  // namespace
}  // namespace efs::mission
