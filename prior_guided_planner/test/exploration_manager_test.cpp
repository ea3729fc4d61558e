// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/exploration_manager.h"
#include "efs_common/testing/config_error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "efs_common/config_check.h"
#include "observation_map_test_scenes.h"
#include "prior_guided_planner/prior_from_bundle.h"
#include "prior_map_tools/prior_map_builder.h"
#include "prior_map_tools/sketch_loader.h"

namespace efs::planner {
namespace {

using testing::Scene;

// A closed corridor room 15.6 m x 6 m x 3 m (the inside of a box).
Scene corridorRoom() {
  Scene s;
  s.room = {Eigen::Vector3d(0.15, -2.85, 0.15), Eigen::Vector3d(15.75, 3.15, 3.15)};
  return s;
}

std::vector<Eigen::Vector3f> toFloat(const std::vector<Eigen::Vector3d>& pts) {
  std::vector<Eigen::Vector3f> out;
  for (const auto& p : pts) out.push_back(p.cast<float>());
  return out;
}

void scanFrom(ExplorationManager& m, const Scene& s, const Eigen::Vector3d& o) {
  m.insertScan(o, toFloat(s.scanSphere(o, 1.0)));
}

// Where most tests start, and the corridor room scanned once from there.
Eigen::Vector3d corridorStart() { return {2.0, 0.1, 1.6}; }
void scanCorridor(ExplorationManager& m) { scanFrom(m, corridorRoom(), corridorStart()); }

RobotPose at(const Eigen::Vector3d& p, double yaw = 0.0) {
  RobotPose r;
  r.position_world_m = p;
  r.yaw_rad = yaw;
  return r;
}

TEST(ExplorationManager, WaitsForDataThenProducesAGoalAhead) {
  ExplorationManagerConfig c;
  c.tour_lookahead_m = 0.0;  // the goal is the first viewpoint (look-ahead: its own test)
  // With the default grazing limit one scan leaves frontier only at the corridor's far end,
  // beyond the goal's reach (staging: its own test), and the room's unseen pockets are too small
  // to be openings; the strict limit leaves frontier within the reach.
  c.observation.facing_min_cosine = testing::kStrictFacingMinCosine;
  ExplorationManager m(c, std::nullopt);
  const Eigen::Vector3d start = corridorStart();
  const ExplorationTarget& t0 = m.update(0.0, at(start));
  EXPECT_EQ(t0.state, ExplorationState::kWaitingForData);
  EXPECT_FALSE(t0.has_goal);
  EXPECT_NE(t0.message.find("no scan"), std::string::npos);

  scanCorridor(m);
  const ExplorationTarget& t = m.update(0.1, at(start));
  ASSERT_EQ(t.state, ExplorationState::kExploring) << t.message;
  ASSERT_TRUE(t.has_goal);
  EXPECT_TRUE(t.replanned);
  EXPECT_EQ(t.mode_used, BaselineMode::kPriorFree);  // no prior
  EXPECT_FALSE(t.active_hypothesis_id.has_value());
  EXPECT_GT(t.goal_world_m.x(), start.x());  // the unexplored part of the corridor is ahead
  EXPECT_TRUE(m.occupancy().isSafe(t.goal_world_m, 0.4, false));
  ASSERT_FALSE(t.tour_world_m.empty());
  EXPECT_TRUE(t.tour_world_m.front().isApprox(t.goal_world_m));
  ASSERT_NE(m.lastPlan(), nullptr);
  EXPECT_EQ(m.lastPlan()->tour.viewpoints.size(), t.tour_world_m.size());
  EXPECT_FALSE(m.viewpoints().empty());
  // The look-at point is the goal's frontier cluster, which the goal viewpoint faces.
  EXPECT_LT((t.look_at_world_m - t.goal_world_m).norm(), 8.0);
}

TEST(ExplorationManager, NoReplanBeforeThePeriodUnlessTheTargetIsReached) {
  ExplorationManagerConfig c;
  c.replan_period_s = 5.0;
  ExplorationManager m(c, std::nullopt);
  const Eigen::Vector3d start = corridorStart();
  scanCorridor(m);
  ASSERT_TRUE(m.update(0.0, at(start)).replanned);
  EXPECT_EQ(m.target().replan_reason, ReplanReason::kFirstPlan);
  const Eigen::Vector3d goal = m.target().goal_world_m;
  EXPECT_FALSE(m.update(1.0, at(start)).replanned);
  EXPECT_TRUE(m.target().goal_world_m.isApprox(goal));
  EXPECT_TRUE(m.update(5.5, at(start)).replanned);  // period elapsed
  EXPECT_EQ(m.target().replan_reason, ReplanReason::kPeriod);
  const Eigen::Vector3d goal2 = m.target().goal_world_m;
  // Reaching the target replans at once, and the reached viewpoint is not the target again.
  const ExplorationTarget& t = m.update(5.6, at(m.target().viewpoint_world_m));
  EXPECT_TRUE(t.replanned);
  EXPECT_EQ(t.replan_reason, ReplanReason::kTargetReached);
  EXPECT_STREQ(toString(t.replan_reason), "target_reached");
  if (t.has_goal) {
    EXPECT_GT((t.goal_world_m - goal2).norm(), 1e-6);
  }
}

// The node updates on a 2 Hz timer, between which the vehicle flies 1.5-2 m, through the
// viewpoints of a tour: a viewpoint its path passed within target_reached_m is reached, whether
// or not an update found it there.
TEST(ExplorationManager, AViewpointPassedBetweenUpdatesCountsAsReached) {
  ExplorationManagerConfig c;
  c.replan_period_s = 5.0;
  // The goal is the viewpoint itself (no look-ahead, no stage, no half-way replan), as with the
  // first test's strict grazing limit.
  c.tour_lookahead_m = 0.0;
  c.observation.facing_min_cosine = testing::kStrictFacingMinCosine;
  const auto firstTarget = [&](ExplorationManager& m) {
    scanCorridor(m);
    EXPECT_TRUE(m.update(0.0, at(corridorStart())).replanned);
    EXPECT_TRUE(m.target().goal_world_m.isApprox(m.target().viewpoint_world_m));
    return m.target();
  };
  const Eigen::Vector3d across(1.5, 0.0, 0.0), aside(0.0, 1.5, 0.0);
  {
    // Flown past 1.5 m beside it: not reached, no replan inside the period.
    ExplorationManager m(c, std::nullopt);
    const ExplorationTarget first = firstTarget(m);
    ASSERT_TRUE(first.has_goal && first.goal_viewpoint_id);
    const Eigen::Vector3d v = first.viewpoint_world_m;
    EXPECT_FALSE(m.update(1.0, at(v - across + aside)).replanned);
    EXPECT_FALSE(m.update(1.5, at(v + across + aside)).replanned);
    EXPECT_EQ(m.target().goal_viewpoint_id, first.goal_viewpoint_id);
  }
  {
    // Flown through it between two updates, neither within 1 m of it: reached.
    ExplorationManager m(c, std::nullopt);
    const ExplorationTarget first = firstTarget(m);
    ASSERT_TRUE(first.has_goal && first.goal_viewpoint_id);
    const Eigen::Vector3d v = first.viewpoint_world_m;
    ASSERT_GT(c.target_reached_m, 0.0);
    ASSERT_LT(c.target_reached_m, across.norm());
    EXPECT_FALSE(m.update(1.0, at(v - across)).replanned);
    const ExplorationTarget& t = m.update(1.5, at(v + across));
    EXPECT_TRUE(t.replanned);
    EXPECT_EQ(t.replan_reason, ReplanReason::kTargetReached);
    EXPECT_NE(t.goal_viewpoint_id, first.goal_viewpoint_id);
  }
  {
    // A jump across it (an odometry reset, 12 m in one step) is no path: not reached.
    ExplorationManager m(c, std::nullopt);
    const ExplorationTarget first = firstTarget(m);
    ASSERT_TRUE(first.has_goal && first.goal_viewpoint_id);
    const Eigen::Vector3d v = first.viewpoint_world_m;
    EXPECT_FALSE(m.update(1.0, at(v - 4.0 * across)).replanned);
    EXPECT_FALSE(m.update(1.5, at(v + 4.0 * across)).replanned);
    EXPECT_EQ(m.target().goal_viewpoint_id, first.goal_viewpoint_id);
  }
}

// A scan that sees the target's frontier well (here: taken from the target viewpoint while the
// vehicle is still at the start) removes the viewpoint; the next update replans at once, inside
// the period, and says why.
TEST(ExplorationManager, ATargetWhoseFrontierWasSeenIsReplacedAtOnce) {
  ExplorationManagerConfig c;
  c.replan_period_s = 100.0;
  c.tour_lookahead_m = 0.0;
  c.observation.facing_min_cosine = testing::kStrictFacingMinCosine;
  ExplorationManager m(c, std::nullopt);
  const Eigen::Vector3d start = corridorStart();
  scanCorridor(m);
  ASSERT_TRUE(m.update(0.0, at(start)).has_goal) << m.target().message;
  const int first = *m.target().goal_viewpoint_id;
  const Eigen::Vector3d viewpoint = m.target().viewpoint_world_m;
  ASSERT_GT((viewpoint - start).norm(), c.target_reached_m);
  EXPECT_FALSE(m.update(0.1, at(start)).replanned);
  scanFrom(m, corridorRoom(), viewpoint);
  const ExplorationTarget& t = m.update(0.2, at(start));
  EXPECT_TRUE(t.replanned);
  EXPECT_EQ(t.replan_reason, ReplanReason::kTargetGone);
  if (t.goal_viewpoint_id) {
    EXPECT_NE(*t.goal_viewpoint_id, first);
  }
}

// Standing at a viewpoint without the scans clearing its frontier: the other viewpoints of that
// cluster (and its re-samples) are not the next target, unless skip_looked_at_clusters is off.
TEST(ExplorationManager, AReachedViewpointsClusterIsNotTargetedAgain) {
  ExplorationManagerConfig c;
  c.tour_lookahead_m = 0.0;  // the goal is the viewpoint, look_at its cluster's centroid
  c.observation.facing_min_cosine = testing::kStrictFacingMinCosine;
  // No scan comes while the robot stands at the targets: the end is taken at once.
  c.finish_confirmation_s = 0.0;
  ExplorationManagerConfig off = c;
  off.skip_looked_at_clusters = false;
  // The targets after standing (unscanned) at each of the first `steps` targets in turn.
  const auto lookAts = [](const ExplorationManagerConfig& config, int steps,
                          std::string* last_message) {
    ExplorationManager m(config, std::nullopt);
    scanCorridor(m);
    std::vector<Eigen::Vector3d> out;
    double time = 0.0;
    m.update(time, at(corridorStart()));
    for (int i = 0; i < steps && m.target().has_goal; ++i) {
      out.push_back(m.target().look_at_world_m);
      time += 0.1;
      m.update(time, at(m.target().viewpoint_world_m));
      *last_message = m.target().message;
    }
    return out;
  };
  std::string message_on, message_off;
  const std::vector<Eigen::Vector3d> on = lookAts(c, 40, &message_on);
  const std::vector<Eigen::Vector3d> without = lookAts(off, 40, &message_off);
  // Without the rule the vehicle comes back to a cluster it stood at (its second viewpoint).
  const auto revisits = [](const std::vector<Eigen::Vector3d>& look_ats) {
    int n = 0;
    for (size_t i = 1; i < look_ats.size(); ++i)
      for (size_t j = 0; j < i; ++j)
        if ((look_ats[i] - look_ats[j]).norm() < 1e-6) {
          ++n;
          break;
        }
    return n;
  };
  ASSERT_GT(revisits(without), 0) << "the scene needs clusters with two viewpoints";
  EXPECT_EQ(revisits(on), 0);
  EXPECT_LT(on.size(), without.size());
  EXPECT_NE(message_on.find("looked at from a reached viewpoint"), std::string::npos) << message_on;
}

// A robot that makes no progress toward its target (the local planner found no way there):
// the target is set aside and the next one gets its turn. When none is left, what was set aside
// is tried again at once instead of hovering through the retry time, and a viewpoint that has
// had unreachable_attempts is given up: the exploration finishes, naming how many were left.
TEST(ExplorationManager, TargetsWithoutProgressAreRetriedThenGivenUp) {
  const Scene room = corridorRoom();
  ExplorationManagerConfig c;
  c.target_progress_timeout_s = 10.0;
  c.unreachable_retry_s = 5000.0;
  c.unreachable_attempts = 2;
  c.finish_confirmation_s = 0.0;  // no scan comes while the robot hovers
  ExplorationManager m(c, std::nullopt);
  const Eigen::Vector3d start(2.0, 0.1, 1.6);
  scanFrom(m, room, start);
  ASSERT_EQ(m.update(0.0, at(start)).state, ExplorationState::kExploring);
  const int first = *m.target().goal_viewpoint_id;
  std::vector<std::pair<double, int>> changes;  // (time, new target id)
  std::map<int, int> turns{{first, 1}};         // how often each viewpoint became the target
  double t = 0.0;
  int last = first;
  bool retried_early = false;
  while (t < 4000.0 && m.target().state != ExplorationState::kFinished) {
    t += 0.5;
    m.update(t, at(start));
    retried_early |= m.target().message.find("retried early") != std::string::npos;
    if (m.target().goal_viewpoint_id && *m.target().goal_viewpoint_id != last) {
      if (changes.empty()) {
        EXPECT_EQ(m.target().replan_reason, ReplanReason::kNoProgress);
      }
      last = *m.target().goal_viewpoint_id;
      changes.emplace_back(t, last);
      ++turns[last];
    }
  }
  ASSERT_FALSE(changes.empty());
  EXPECT_GE(changes.front().first, 10.0);  // held for the whole timeout ...
  EXPECT_LE(changes.front().first, 11.5);  // ... and not longer
  ASSERT_EQ(m.target().state, ExplorationState::kFinished) << m.target().message;
  EXPECT_LT(t, c.unreachable_retry_s);  // the retry time was not waited out
  EXPECT_TRUE(retried_early);
  EXPECT_FALSE(m.target().has_goal);
  // A viewpoint retried right after its own first turn keeps the target without a change.
  for (const auto& [id, n] : turns) EXPECT_LE(n, c.unreachable_attempts) << "viewpoint " << id;
  EXPECT_GT(changes.size(), turns.size() - 1);  // some came back for their second attempt
  EXPECT_EQ(m.inputStats().viewpoints_given_up, turns.size());
  EXPECT_NE(m.target().message.find(std::to_string(turns.size()) + " left unvisited, given up"),
            std::string::npos)
      << m.target().message;
  // Once finished it stays finished: nothing given up comes back. Without a goal every update
  // looks again.
  EXPECT_TRUE(m.update(t + c.unreachable_retry_s + 1.0, at(start)).replanned);
  EXPECT_EQ(m.target().replan_reason, ReplanReason::kNoGoal);
  EXPECT_EQ(m.target().state, ExplorationState::kFinished) << m.target().message;

  // Progress keeps a target: moving toward it (0.4 m/s) never sets it aside.
  c.replan_period_s = 0.5;
  c.target_progress_timeout_s = 2.0;
  ExplorationManager moving(c, std::nullopt);
  scanFrom(moving, room, start);
  moving.update(0.0, at(start));
  const Eigen::Vector3d vp = moving.target().viewpoint_world_m;
  EXPECT_EQ(moving.target().state, ExplorationState::kExploring);
  const int steps = static_cast<int>(std::floor(((vp - start).norm() - 1.2) / 0.04));
  ASSERT_GT(steps * 0.1, c.target_progress_timeout_s);
  for (int i = 1; i <= steps; ++i) {
    const Eigen::Vector3d p = start + (vp - start).normalized() * (0.04 * i);
    moving.update(i * 0.1, at(p));
    EXPECT_NE(moving.target().message.find("exploring"), std::string::npos);
    EXPECT_EQ(moving.target().message.find("set aside"), std::string::npos)
        << "at " << i << " s: " << moving.target().message;
  }
}

// The local planner gave up on the goal: its viewpoint is set aside at once (not after the
// progress watchdog) and another target is planned on the next update; a report about a goal
// that is no longer current, or a non-finite one, changes nothing.
TEST(ExplorationManager, AGoalTheLocalPlannerGaveUpOnIsSetAsideAtOnce) {
  ExplorationManagerConfig c;
  // Two targets are needed: with the default grazing limit one scan leaves frontier only at the
  // corridor's far end.
  c.observation.facing_min_cosine = testing::kStrictFacingMinCosine;
  c.target_progress_timeout_s = 10.0;
  c.unreachable_retry_s = 100.0;
  ExplorationManager m(c, std::nullopt);
  const Eigen::Vector3d start = corridorStart();
  scanCorridor(m);
  ASSERT_EQ(m.update(0.0, at(start)).state, ExplorationState::kExploring);
  const int first = *m.target().goal_viewpoint_id;
  const Eigen::Vector3d goal = m.target().goal_world_m;

  EXPECT_EQ(m.reportGoalUnreachable(goal + Eigen::Vector3d(0.5, 0, 0), 0.5),
            GoalRefusal::kNotCurrent);
  EXPECT_EQ(m.reportGoalUnreachable(
                Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()), 0.5),
            GoalRefusal::kNotCurrent);
  m.update(0.5, at(start));
  EXPECT_EQ(*m.target().goal_viewpoint_id, first);
  EXPECT_EQ(m.inputStats().goals_refused, 0u);

  ASSERT_EQ(m.reportGoalUnreachable(goal, 0.6), GoalRefusal::kSetAside);
  const ExplorationTarget& t = m.update(0.7, at(start));
  EXPECT_TRUE(t.replanned);
  EXPECT_EQ(t.replan_reason, ReplanReason::kGoalRefused);
  ASSERT_EQ(t.state, ExplorationState::kExploring) << t.message;
  EXPECT_NE(*t.goal_viewpoint_id, first);
  EXPECT_NE(t.message.find("set aside"), std::string::npos) << t.message;
  EXPECT_NE(t.message.find("no way to the goal"), std::string::npos) << t.message;
  EXPECT_EQ(m.inputStats().goals_refused, 1u);
  // The refused viewpoint stays aside until unreachable_retry_s has passed, and the refused
  // goal point is not sent again for another viewpoint either (the look-ahead along its path
  // could land on it).
  for (double time = 1.0; time < 50.0; time += 1.0) {
    m.update(time, at(start));
    if (m.target().goal_viewpoint_id) {
      EXPECT_NE(*m.target().goal_viewpoint_id, first);
    }
    if (m.target().has_goal) {
      EXPECT_GT((m.target().goal_world_m - goal).norm(), 0.5) << "at " << time << " s";
    }
  }
}

// The local planner gave up on a goal whose viewpoint is within unreachable_near_m of the
// vehicle (a viewpoint below it, over a floor nobody has seen): the viewpoint counts as reached.
// It is not retried after unreachable_retry_s nor when nothing else is left (a set-aside one
// would draw the vehicle back to it), and it is not counted as given up.
TEST(ExplorationManager, AGoalRefusedNearTheVehicleCountsItsViewpointAsReached) {
  ExplorationManagerConfig c;
  c.unreachable_retry_s = 1.0;
  c.unreachable_near_m = 3.0;  // between the 2 m below and the first target from the start
  ExplorationManager m(c, std::nullopt);
  const Eigen::Vector3d start = corridorStart();
  scanCorridor(m);
  ASSERT_EQ(m.update(0.0, at(start)).state, ExplorationState::kExploring);
  const int refused = *m.target().goal_viewpoint_id;
  const Eigen::Vector3d viewpoint = m.target().viewpoint_world_m;
  // Hovering 2 m from the viewpoint (out of target_reached_m), the goal unchanged.
  const Eigen::Vector3d beside = viewpoint - 2.0 * (viewpoint - start).normalized();
  ASSERT_EQ(*m.update(0.1, at(beside)).goal_viewpoint_id, refused);
  ASSERT_EQ(m.reportGoalUnreachable(m.target().goal_world_m, 0.2), GoalRefusal::kCountedReached);
  const ExplorationTarget& t = m.update(0.3, at(beside));
  EXPECT_TRUE(t.replanned);
  EXPECT_NE(t.message.find("counted as reached"), std::string::npos) << t.message;
  EXPECT_EQ(m.inputStats().goals_refused, 1u);
  EXPECT_EQ(m.inputStats().goals_refused_near, 1u);

  // Long past the retry time (and short of the progress watchdog's, which would set the other
  // targets aside, the robot never moving), the viewpoint does not come back.
  ASSERT_LT(8.0, c.target_progress_timeout_s);
  for (double time = 1.0; time < 8.0; time += 0.5) {
    m.update(time, at(beside));
    if (m.target().goal_viewpoint_id) {
      EXPECT_NE(*m.target().goal_viewpoint_id, refused);
    }
    if (m.target().state == ExplorationState::kFinished) break;
  }
  EXPECT_EQ(m.inputStats().viewpoints_given_up, 0u);

  // Farther than unreachable_near_m the same report sets the viewpoint aside.
  ExplorationManager far(c, std::nullopt);
  scanCorridor(far);
  far.update(0.0, at(start));
  ASSERT_GT((far.target().viewpoint_world_m - start).norm(), 3.0);
  ASSERT_EQ(far.reportGoalUnreachable(far.target().goal_world_m, 0.1), GoalRefusal::kSetAside);
  EXPECT_NE(far.update(0.2, at(start)).message.find("set aside"), std::string::npos);
  EXPECT_EQ(far.inputStats().goals_refused_near, 0u);
}

// The ROS graph's endless cycle (seen in mission_wrong_sketch): the local planner gives up on
// every goal it is sent. Each viewpoint gets unreachable_attempts, the set-aside ones are
// retried without waiting out the retry time, and the exploration ends, naming the leftovers.
TEST(ExplorationManager, EveryGoalRefusedEndsTheExplorationWithTheLeftoversNamed) {
  ExplorationManagerConfig c;
  c.unreachable_retry_s = 1e5;
  c.unreachable_attempts = 2;
  c.finish_confirmation_s = 0.0;  // no scan comes while the robot hovers
  ExplorationManager m(c, std::nullopt);
  const Eigen::Vector3d start = corridorStart();
  scanCorridor(m);
  double time = 0.0;
  m.update(time, at(start));
  while (m.target().state != ExplorationState::kFinished && time < 1000.0) {
    if (m.target().has_goal) {
      EXPECT_NE(m.reportGoalUnreachable(m.target().goal_world_m, time), GoalRefusal::kNotCurrent);
    }
    time += 0.5;
    m.update(time, at(start));
  }
  ASSERT_EQ(m.target().state, ExplorationState::kFinished) << m.target().message;
  EXPECT_GT(m.inputStats().viewpoints_given_up, 0u);
  // At most two refusals each (a viewpoint whose goal lies on a refused one is set aside
  // without being sent).
  EXPECT_LE(m.inputStats().goals_refused, 2 * m.inputStats().viewpoints_given_up);
  EXPECT_NE(m.target().message.find(std::to_string(m.inputStats().viewpoints_given_up) +
                                    " left unvisited, given up as unreachable after 2"),
            std::string::npos)
      << m.target().message;
}

// A viewpoint beyond max_goal_distance_m reaches the local planner in stages along its path.
TEST(ExplorationManager, AFarViewpointIsHandedOnInStages) {
  const Scene room = corridorRoom();
  const Eigen::Vector3d start(2.0, 0.1, 1.6);
  ExplorationManagerConfig whole_config;
  whole_config.tour_lookahead_m = 0.0;  // stages only
  // A first viewpoint within the default reach, which the default grazing limit does not leave.
  whole_config.observation.facing_min_cosine = testing::kStrictFacingMinCosine;
  ExplorationManager whole(whole_config, std::nullopt);
  scanFrom(whole, room, start);
  const ExplorationTarget t_whole = whole.update(0.0, at(start));
  ASSERT_TRUE(t_whole.has_goal) << t_whole.message;
  const double vp_distance_m = (t_whole.viewpoint_world_m - start).head<2>().norm();
  ASSERT_GT(vp_distance_m, 2.0);  // the scene has a far target
  EXPECT_TRUE(t_whole.goal_world_m.isApprox(t_whole.viewpoint_world_m));

  ExplorationManagerConfig c = whole_config;
  c.max_goal_distance_m = 0.5 * vp_distance_m;
  ExplorationManager staged(c, std::nullopt);
  scanFrom(staged, room, start);
  const ExplorationTarget t = staged.update(0.0, at(start));
  ASSERT_TRUE(t.has_goal) << t.message;
  EXPECT_TRUE(t.viewpoint_world_m.isApprox(t_whole.viewpoint_world_m));
  EXPECT_LE((t.goal_world_m - start).head<2>().norm(), c.max_goal_distance_m + 1e-9);
  EXPECT_GT((t.goal_world_m - start).head<2>().norm(), c.max_goal_distance_m - 0.2);
  EXPECT_TRUE(staged.occupancy().isSafe(t.goal_world_m, 0.3, false));
  EXPECT_NE(t.message.find("staged goal"), std::string::npos) << t.message;
  EXPECT_TRUE(t.look_at_world_m.isApprox(t.goal_world_m));               // facing the way it flies
  EXPECT_FALSE(t_whole.look_at_world_m.isApprox(t_whole.goal_world_m));  // facing the frontier
  // Half-way to the stage the next one is planned, closer to the viewpoint.
  const Eigen::Vector3d mid = 0.5 * (start + t.goal_world_m);
  const Eigen::Vector3d stage1 = t.goal_world_m;
  const ExplorationTarget& t2 = staged.update(0.1, at(mid + 0.3 * (stage1 - mid)));
  EXPECT_TRUE(t2.replanned);
  ASSERT_TRUE(t2.has_goal);
  EXPECT_LT((t2.goal_world_m - t2.viewpoint_world_m).norm(),
            (stage1 - t2.viewpoint_world_m).norm() - 0.5);
}

/// Length of the polyline p0 ... pn up to the point of it nearest to q, and that distance.
std::pair<double, double> alongPolyline(const std::vector<Eigen::Vector3d>& p,
                                        const Eigen::Vector3d& q) {
  double walked = 0.0, best_d = std::numeric_limits<double>::infinity(), best_s = 0.0;
  for (size_t i = 0; i + 1 < p.size(); ++i) {
    const Eigen::Vector3d d = p[i + 1] - p[i];
    const double len = d.norm();
    const double t = len > 0 ? std::clamp((q - p[i]).dot(d) / (len * len), 0.0, 1.0) : 0.0;
    const double dist = (p[i] + t * d - q).norm();
    if (dist < best_d) best_d = dist, best_s = walked + t * len;
    walked += len;
  }
  return {best_s, best_d};
}

// The goal lies along the tour, at or past the first viewpoint (how far: goal_along_path_test),
// and the sensor faces the way the vehicle flies.
TEST(ExplorationManager, TheGoalLiesAheadAlongTheTour) {
  const Scene room = corridorRoom();
  const Eigen::Vector3d start(2.0, 0.1, 1.6);
  // A first viewpoint within the look-ahead, which the default grazing limit does not leave.
  ExplorationManagerConfig along;
  along.observation.facing_min_cosine = testing::kStrictFacingMinCosine;
  ExplorationManagerConfig at_viewpoint = along;
  at_viewpoint.tour_lookahead_m = 0.0;
  ExplorationManager stop(at_viewpoint, std::nullopt), pass(along, std::nullopt);
  scanFrom(stop, room, start);
  scanFrom(pass, room, start);
  const ExplorationTarget a = stop.update(0.0, at(start));
  const ExplorationTarget b = pass.update(0.0, at(start));
  ASSERT_TRUE(a.has_goal && b.has_goal);
  ASSERT_GE(b.tour_world_m.size(), 2u) << "the scene needs a tour of two viewpoints";
  EXPECT_TRUE(a.goal_world_m.isApprox(a.viewpoint_world_m));
  EXPECT_TRUE(b.viewpoint_world_m.isApprox(a.viewpoint_world_m));  // the same plan
  // On the tour's path, farther along it than the first viewpoint, within the look-ahead.
  std::vector<Eigen::Vector3d> tour{start};
  tour.insert(tour.end(), b.tour_world_m.begin(), b.tour_world_m.end());
  const auto [s_goal, off_goal] = alongPolyline(tour, b.goal_world_m);
  const auto [s_first, off_first] = alongPolyline(tour, b.viewpoint_world_m);
  EXPECT_LT(off_goal, 1.0);  // searched legs may bend around what the straight tour crosses
  EXPECT_GE(s_goal, s_first - 0.05);  // never short of the first viewpoint
  EXPECT_GT((b.goal_world_m - start).norm(), 1.0);
  EXPECT_LE((b.goal_world_m - start).head<2>().norm(),
            ExplorationManagerConfig{}.tour_lookahead_m + 1e-6);
  EXPECT_TRUE(pass.occupancy().isSafe(b.goal_world_m, 0.3, false));
  EXPECT_TRUE(b.look_at_world_m.isApprox(b.goal_world_m));  // facing the way it flies
  (void)off_first;
}

// Flying from goal to goal (a scan at each) explores the closed room; once no viewpoint is left
// the manager holds for finish_confirmation_s, then reports kFinished, and each reached goal
// moved on. The room is a 40 m corridor: a surface counts as well observed from 12 m, so the
// 15.6 m one would be done after a single goal.
TEST(ExplorationManager, ClosedLoopFinishesAClosedRoom) {
  Scene room = corridorRoom();
  room.room.hi.x() = 39.75;
  const ExplorationManagerConfig c;
  ExplorationManager m(c, std::nullopt);
  Eigen::Vector3d pos(2.0, 0.1, 1.6);
  scanFrom(m, room, pos);
  double t_s = 0.0;
  int goals = 0;
  std::optional<double> nothing_left_s;
  for (int step = 0; step < 60; ++step) {
    const ExplorationTarget& t = m.update(t_s, at(pos));
    if (t.state == ExplorationState::kFinished) break;
    ASSERT_EQ(t.state, ExplorationState::kExploring) << t.message;
    t_s += 0.5;
    if (!t.has_goal) {  // nothing left: the end is being confirmed, the scans go on
      EXPECT_NE(t.message.find("no viewpoint remains for"), std::string::npos) << t.message;
      if (!nothing_left_s) nothing_left_s = t_s - 0.5;
      scanFrom(m, room, pos);
      continue;
    }
    ASSERT_FALSE(nothing_left_s) << "a viewpoint came back without anything new seen";
    EXPECT_GT((t.goal_world_m - pos).norm(), 1e-6) << "the goal must move on when reached";
    EXPECT_TRUE(room.room.lo.x() < t.goal_world_m.x() && t.goal_world_m.x() < room.room.hi.x());
    pos = t.goal_world_m;
    scanFrom(m, room, pos);
    ++goals;
  }
  EXPECT_EQ(m.target().state, ExplorationState::kFinished) << m.target().message;
  EXPECT_FALSE(m.target().has_goal);
  EXPECT_GE(goals, 2);
  EXPECT_TRUE(m.viewpoints().empty());
  ASSERT_TRUE(nothing_left_s);
  EXPECT_GE(t_s - *nothing_left_s, c.finish_confirmation_s);
  EXPECT_LE(t_s - *nothing_left_s, c.finish_confirmation_s + 0.5);
  // Being finished is stable while nothing new is seen.
  EXPECT_EQ(m.update(t_s + 10.0, at(pos)).state, ExplorationState::kFinished);
}

// "No viewpoint remains" is the end only once it held finish_confirmation_s with new scans
// inserted meanwhile (a map can sit between two ways on); a viewpoint that appears meanwhile
// starts the exploration again. Hovering without scans (a stalled LIO) never finishes.
TEST(ExplorationManager, TheEndIsConfirmedOnlyAfterItHeldWithNewScans) {
  const Scene room = corridorRoom();
  ExplorationManagerConfig c;
  c.finish_confirmation_s = 2.0;
  // Every corner seen from a few places: nothing is left to plan for.
  const std::vector<Eigen::Vector3d> places = {
      {2.0, 0.1, 1.6}, {8.0, 0.1, 1.6}, {13.5, 0.1, 1.6}, {8.0, -2.0, 0.8}, {8.0, 2.0, 2.4}};
  const auto explored = [&](const ExplorationManagerConfig& config) {
    auto m = std::make_unique<ExplorationManager>(config, std::nullopt);
    for (const Eigen::Vector3d& p : places) scanFrom(*m, room, p);
    return m;
  };
  const Eigen::Vector3d pos = places[1];
  {
    auto m = explored(c);
    const ExplorationTarget& t = m->update(0.0, at(pos));
    ASSERT_EQ(t.state, ExplorationState::kExploring) << t.message;
    ASSERT_FALSE(t.has_goal) << "the scene must leave no viewpoint";
    EXPECT_NE(t.message.find("no viewpoint remains for 0 s"), std::string::npos) << t.message;
    // Long enough, but no scan came: not the end.
    EXPECT_EQ(m->update(5.0, at(pos)).state, ExplorationState::kExploring);
    scanFrom(*m, room, pos);
    EXPECT_EQ(m->update(5.1, at(pos)).state, ExplorationState::kFinished) << m->target().message;
  }
  {
    auto m = explored(c);
    m->update(0.0, at(pos));
    scanFrom(*m, room, pos);
    EXPECT_EQ(m->update(1.0, at(pos)).state, ExplorationState::kExploring);  // too soon
    // The far wall turns out to be a door: the corridor goes on, and so does the exploration.
    Scene longer = room;
    longer.room.hi.x() = 30.75;
    for (int i = 0; i < 3; ++i) scanFrom(*m, longer, places[2]);
    const ExplorationTarget& t = m->update(1.5, at(places[2]));
    EXPECT_NE(t.state, ExplorationState::kFinished) << t.message;
    EXPECT_FALSE(m->viewpoints().empty()) << t.message;
    // Past the confirmation time of the first "nothing left", the corridor still is not done.
    scanFrom(*m, longer, places[2]);
    EXPECT_NE(m->update(2.5, at(places[2])).state, ExplorationState::kFinished);
  }
  {
    ExplorationManagerConfig at_once = c;
    at_once.finish_confirmation_s = 0.0;
    auto m = explored(at_once);
    EXPECT_EQ(m->update(0.0, at(pos)).state, ExplorationState::kFinished);
  }
}

TEST(ExplorationManager, NonFiniteInputIsDroppedAndReported) {
  const Scene room = corridorRoom();
  ExplorationManager m(ExplorationManagerConfig{}, std::nullopt);
  const Eigen::Vector3d start(2.0, 0.1, 1.6);
  std::vector<Eigen::Vector3f> pts = toFloat(room.scanSphere(start, 1.0));
  const size_t n_good = pts.size();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  pts.emplace_back(nan, 0.f, 1.f);
  pts.emplace_back(1.f, std::numeric_limits<float>::infinity(), 1.f);
  m.insertScan(start, pts);
  EXPECT_EQ(m.inputStats().points_dropped_nonfinite, 2u);
  EXPECT_EQ(m.inputStats().scans_inserted, 1u);
  const ExplorationTarget& t = m.update(0.0, at(start));
  EXPECT_TRUE(t.has_goal);
  EXPECT_NE(t.message.find("non-finite"), std::string::npos) << t.message;
  EXPECT_GT(n_good, 1000u);

  // A scan of only NaN and an empty scan change nothing; a NaN origin is refused.
  const size_t surface = m.observationMap().numSurfaceCells();
  m.insertScan(start, {Eigen::Vector3f(nan, nan, nan)});
  m.insertScan(start, {});
  m.insertScan(Eigen::Vector3d(std::nan(""), 0, 0), toFloat(room.scanSphere(start, 2.0)));
  EXPECT_EQ(m.observationMap().numSurfaceCells(), surface);
  EXPECT_EQ(m.inputStats().scans_inserted, 1u);
  EXPECT_EQ(m.inputStats().scans_empty, 2u);
  EXPECT_EQ(m.inputStats().scans_rejected, 1u);
  EXPECT_NE(m.update(0.1, at(start)).message.find("sensor origin"), std::string::npos);

  // A non-finite pose is refused, the last target kept.
  const Eigen::Vector3d goal = m.target().goal_world_m;
  const ExplorationTarget& bad = m.update(0.2, at(Eigen::Vector3d(std::nan(""), 0, 0)));
  EXPECT_FALSE(bad.replanned);
  EXPECT_TRUE(bad.goal_world_m.isApprox(goal));
  EXPECT_NE(bad.message.find("not finite"), std::string::npos);
}

TEST(ExplorationManager, TimeGoingBackwardsIsRefused) {
  ExplorationManager m(ExplorationManagerConfig{}, std::nullopt);
  const Eigen::Vector3d start = corridorStart();
  scanCorridor(m);
  ASSERT_TRUE(m.update(10.0, at(start)).has_goal);
  const Eigen::Vector3d goal = m.target().goal_world_m;
  const ExplorationTarget& t = m.update(5.0, at(start));
  EXPECT_FALSE(t.replanned);
  EXPECT_TRUE(t.has_goal);
  EXPECT_TRUE(t.goal_world_m.isApprox(goal));
  EXPECT_NE(t.message.find("backwards"), std::string::npos) << t.message;
  EXPECT_EQ(m.inputStats().updates_rejected, 1u);
  // Time moving on again works; the refused update did not move the clock.
  EXPECT_TRUE(m.update(11.5, at(start)).replanned);
}

GuidepointPrior corridorPrior(int n, double spacing_m) {
  GuidepointPrior g;
  for (int i = 0; i < n; ++i) {
    g.ids.push_back(i);
    g.positions_sketch_m.emplace_back(spacing_m * i, 0.0);
  }
  g.prm_distance_m = CostMatrix(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) g.prm_distance_m(i, j) = spacing_m * std::abs(i - j);
  return g;
}

TEST(ExplorationManager, HypothesesGuideAndBadOnesAreRefused) {
  ExplorationManager m(ExplorationManagerConfig{}, corridorPrior(4, 5.0));
  const Eigen::Vector3d start = corridorStart();
  scanCorridor(m);
  Hypothesis bad;
  bad.id = 3;
  bad.T_world_sketch.scale = std::nan("");
  Hypothesis neg;
  neg.id = 4;
  neg.T_world_sketch.scale = -1.0;
  Hypothesis good;
  good.id = 9;
  good.T_world_sketch = Sim2(0.0, 1.0, Eigen::Vector2d(1.0, 0.0));
  m.setHypotheses({bad, neg, good});
  EXPECT_EQ(m.inputStats().hypotheses_rejected, 2u);
  ASSERT_EQ(m.hypotheses().size(), 1u);
  const ExplorationTarget& t = m.update(0.0, at(start));
  ASSERT_TRUE(t.has_goal) << t.message;
  EXPECT_NE(t.message.find("hypothesis 3"), std::string::npos) << t.message;
  EXPECT_EQ(t.mode_used, BaselineMode::kProposed);
  EXPECT_EQ(t.active_hypothesis_id, std::optional<int>(9));
  const HypothesisAttachment* a = m.activeAttachment();
  ASSERT_NE(a, nullptr);
  ASSERT_EQ(a->guidepoints_world_m.size(), 4u);
  EXPECT_TRUE(a->guidepoints_world_m[1].isApprox(Eigen::Vector2d(6.0, 0.0)));  // shifted by 1 m
  EXPECT_FALSE(m.activeGuidepointSequence().empty());
  // New hypotheses replan at once even inside the period.
  EXPECT_FALSE(m.update(0.1, at(start)).replanned);
  m.setHypotheses({});
  const ExplorationTarget& t2 = m.update(0.2, at(start));
  EXPECT_TRUE(t2.replanned);
  EXPECT_EQ(t2.replan_reason, ReplanReason::kNewHypotheses);
  EXPECT_EQ(t2.mode_used, BaselineMode::kPriorFree);
  EXPECT_EQ(m.activeAttachment(), nullptr);
  EXPECT_TRUE(m.activeGuidepointSequence().empty());
  // Still none (a registration frame without a hypothesis) is no change: no replan inside the
  // period, so a flight with a sketch that never registers flies as the prior-free one.
  m.setHypotheses({});
  EXPECT_FALSE(m.update(0.3, at(start)).replanned);
}

// Once no viewpoint is left the plan has no guiding hypothesis, but the openings the sketch
// vouches for are still looked for near its guidepoints and its predicted free space: those of
// the last guided plan, kept while hypotheses remain.
TEST(ExplorationManager, TheGuidingGuidepointsOutliveAPlanWithoutViewpoints) {
  ExplorationManagerConfig c;
  c.finish_confirmation_s = 2.0;
  GuidepointPrior prior = corridorPrior(4, 5.0);
  prior.predicted_free_sketch_m = {Eigen::Vector2d(2.0, 0.5), Eigen::Vector2d(12.0, -0.5)};
  ExplorationManager m(c, prior);
  const Scene room = corridorRoom();
  scanCorridor(m);
  // Turned a quarter and shifted: the free samples must go through the whole transform.
  const Sim2 T_world_sketch(M_PI / 2.0, 1.0, Eigen::Vector2d(10.0, -6.0));
  m.setHypotheses({Hypothesis{9, T_world_sketch, 0.8}});
  ASSERT_TRUE(m.update(0.0, at(corridorStart())).has_goal);
  const HypothesisAttachment* guide = m.activeAttachment();
  ASSERT_NE(guide, nullptr);
  const std::vector<Eigen::Vector2d> guided = guide->guidepoints_world_m;
  ASSERT_EQ(guided.size(), 4u);
  EXPECT_EQ(m.guidingGuidepoints(), guided);
  std::vector<Eigen::Vector2d> places = guided;
  places.emplace_back(9.5, -4.0);  // (2, 0.5) turned: (-0.5, 2), shifted
  places.emplace_back(10.5, 6.0);  // (12, -0.5) turned: (0.5, 12), shifted
  const auto expectPlaces = [&](const std::vector<Eigen::Vector2d>& got) {
    ASSERT_EQ(got.size(), places.size());
    for (size_t i = 0; i < got.size(); ++i)
      EXPECT_TRUE(got[i].isApprox(places[i], 1e-9)) << i << ": " << got[i].transpose();
  };
  expectPlaces(m.vouchingPlaces());
  // Every corner seen: nothing left to plan for, no guiding hypothesis, the guidepoints kept.
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(8.0, 0.1, 1.6), Eigen::Vector3d(13.5, 0.1, 1.6),
                                   Eigen::Vector3d(8.0, -2.0, 0.8), Eigen::Vector3d(8.0, 2.0, 2.4)})
    scanFrom(m, room, p);
  const ExplorationTarget& t = m.update(1.0, at(corridorStart()));
  ASSERT_FALSE(t.has_goal) << t.message;
  EXPECT_EQ(m.activeAttachment(), nullptr);
  EXPECT_EQ(m.guidingGuidepoints(), guided);
  expectPlaces(m.vouchingPlaces());
  // Without hypotheses there is nothing to vouch for.
  m.setHypotheses({});
  m.update(1.5, at(corridorStart()));
  EXPECT_TRUE(m.guidingGuidepoints().empty());
  EXPECT_TRUE(m.vouchingPlaces().empty());
}

TEST(ExplorationManager, GreedyPriorModeFollowsThePredictedCorridor) {
  ExplorationManagerConfig c;
  c.planner.mode = BaselineMode::kGreedyPrior;
  GuidepointPrior prior = corridorPrior(4, 5.0);
  for (double x = 0.5; x < 16.0; x += 1.0)
    for (double y = -2.5; y < 3.0; y += 1.0) prior.predicted_free_sketch_m.emplace_back(x, y);
  ExplorationManager m(c, prior);
  const Eigen::Vector3d start = corridorStart();
  scanCorridor(m);
  m.setHypotheses({Hypothesis{2, Sim2(), 0.7}});
  const ExplorationTarget& t = m.update(0.0, at(start));
  ASSERT_TRUE(t.has_goal) << t.message;
  EXPECT_EQ(t.mode_used, BaselineMode::kGreedyPrior);
  EXPECT_EQ(t.active_hypothesis_id, std::optional<int>(2));
  EXPECT_EQ(t.tour_world_m.size(), 1u);
}

// The last resorts are looked at while looking pays (last_resort_stall). A hall split at x = 5
// by a wall with a 0.6 m slit, scanned at 6 m: the slit's opening is reached and is a dead end,
// nothing else is left. A look through the slit from afar (40 m) then moves the opening on into
// the far part while adding a handful of well-observed cells (the far walls are seen from too
// far): a last resort. Looked at, it opens the far part; given up once the map has not gained
// last_resort_min_gain_fraction for last_resort_patience_s, the flight ends where it is.
struct SlitFlight {
  std::vector<std::string> messages;
  double max_x_m = -1e9;
  ExplorationState end = ExplorationState::kWaitingForData;
};
SlitFlight flyTheSlitHall(const StallConfig& stall) {
  Scene s;
  s.room = {{-5, -4, 0}, {15, 4, 3}};
  s.solids.push_back({{5.0, -4, 0}, {5.3, -0.3, 3}});
  s.solids.push_back({{5.0, 0.3, 0}, {5.3, 4, 3}});
  // A guided flight: a drawing of the hall, its guidepoints in both parts.
  GuidepointPrior prior;
  prior.positions_sketch_m = {{0.0, 0.0}, {3.0, 0.0}, {12.0, 2.0}};
  prior.ids = {0, 1, 2};
  prior.prm_distance_m = CostMatrix(3);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      prior.prm_distance_m(i, j) =
          (prior.positions_sketch_m[i] - prior.positions_sketch_m[j]).norm();
  ExplorationManagerConfig c;
  c.last_resort_stall = stall;
  ExplorationManager m(c, prior);
  m.setHypotheses({Hypothesis{1, Sim2(), 0.9}});
  const auto scan = [&](const Eigen::Vector3d& o, double range_m) {
    m.insertScan(o, toFloat(s.scanSphere(o, 1.0, range_m)));
  };
  const Eigen::Vector3d start(0.0, 0.0, 1.5);
  Eigen::Vector3d pos = start;
  scan(pos, 6.0);
  SlitFlight f;
  bool looked_from_afar = false;
  for (double t_s = 0.0; t_s < 200.0; t_s += 2.0) {
    const ExplorationTarget& t = m.update(t_s, at(pos));
    f.messages.push_back(t.message);
    f.end = t.state;
    if (t.state == ExplorationState::kFinished) break;
    if (t.has_goal) pos = t.goal_world_m;
    f.max_x_m = std::max(f.max_x_m, pos.x());
    if (!t.has_goal && !looked_from_afar) {
      looked_from_afar = true;
      scan(start, 40.0);
    } else {
      scan(pos, 6.0);
    }
  }
  return f;
}

bool anyMessageHas(const SlitFlight& f, const std::string& text) {
  return std::any_of(f.messages.begin(), f.messages.end(),
                     [&](const std::string& m) { return m.find(text) != std::string::npos; });
}

TEST(ExplorationManager, TheLastResortsAreGivenUpOnceTheMapStoppedGaining) {
  StallConfig off;
  off.patience_s = 0.0;
  const SlitFlight looked = flyTheSlitHall(off);  // looked at until none is left
  ASSERT_EQ(looked.end, ExplorationState::kFinished) << looked.messages.back();
  EXPECT_TRUE(anyMessageHas(looked, "moved on looked at again"));
  EXPECT_FALSE(anyMessageHas(looked, "given up:"));
  EXPECT_GT(looked.max_x_m, 8.0);  // the far part was flown into

  // No gain large enough since the first plan, and the patience is over: given up.
  StallConfig impatient;
  impatient.patience_s = 1.0;
  impatient.min_gain_fraction = 1.0;  // the map doubling: not in this flight
  const SlitFlight ended = flyTheSlitHall(impatient);
  ASSERT_EQ(ended.end, ExplorationState::kFinished) << ended.messages.back();
  EXPECT_FALSE(anyMessageHas(ended, "moved on looked at again"));
  EXPECT_NE(ended.messages.back().find("1 last resort(s) given up: "), std::string::npos)
      << ended.messages.back();
  EXPECT_LT(ended.max_x_m, 5.0);  // never through the slit

  // The same gain wanted, but patience left: looked at as without the watch.
  StallConfig patient = impatient;
  patient.patience_s = 100.0;
  const SlitFlight waited = flyTheSlitHall(patient);
  EXPECT_EQ(waited.messages, looked.messages);
}

TEST(ExplorationManager, ConfigErrorsNameTheKey) {
  auto expectKey = [](ExplorationManagerConfig c, const std::string& key) {
    efs::testing::expectConfigErrorNaming([&] { ExplorationManager m(c, std::nullopt); }, key);
  };
  ExplorationManagerConfig c;
  c.replan_period_s = -1.0;
  expectKey(c, "replan_period_s");
  c = {};
  c.target_reached_m = std::nan("");
  expectKey(c, "target_reached_m");
  c = ExplorationManagerConfig{};
  c.target_progress_timeout_s = 0.0;
  expectKey(c, "target_progress_timeout_s");
  c = ExplorationManagerConfig{};
  c.finish_confirmation_s = -1.0;
  expectKey(c, "finish_confirmation_s");
  c = ExplorationManagerConfig{};
  c.unreachable_retry_s = -1.0;
  expectKey(c, "unreachable_retry_s");
  c = {};
  c.unreachable_attempts = 0;
  expectKey(c, "unreachable_attempts");
  c = {};
  c.unreachable_near_m = std::nan("");
  expectKey(c, "unreachable_near_m");
  c = {};
  c.looked_at_fraction = 0.0;
  expectKey(c, "looked_at_fraction");
  c = {};
  c.looked_at_fraction = std::nan("");
  expectKey(c, "looked_at_fraction");
  c = {};
  c.bounds_world_m = Eigen::AlignedBox3d(Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(0, 0, 0));
  expectKey(c, "bounds_world_m");
  c = {};
  c.planner.fe_tsp.v_max_mps = 0.0;
  expectKey(c, "v_max");
  c = {};
  c.openings.search_radius_m = 0.0;
  expectKey(c, "search_radius_m");
  c = {};
  c.near_openings_radius_m = -1.0;
  expectKey(c, "near_openings_radius_m");
  c = {};
  c.near_openings_min_cells = 0;
  expectKey(c, "near_openings_min_cells");
  c = {};
  c.reached_openings.moved_m = std::nan("");
  expectKey(c, "reached_opening_moved_m");
  c = {};
  c.reached_openings.max_visits = 0;
  expectKey(c, "opening_max_visits");
  c = {};
  c.last_resort_stall.patience_s = -1.0;
  expectKey(c, "last_resort_patience_s");
  c = {};
  c.last_resort_stall.min_gain_fraction = 0.0;
  expectKey(c, "last_resort_min_gain_fraction");
}

TEST(ExplorationManager, MalformedPriorIsRefused) {
  GuidepointPrior p = corridorPrior(3, 5.0);
  p.positions_sketch_m[1].x() = std::nan("");
  EXPECT_THROW(ExplorationManager(ExplorationManagerConfig{}, p), std::invalid_argument);
}

// Two rooms with no door between them, drawn as a sketch and pre-processed by prior_map_tools.
efs::prior_map::PriorBundle twoRoomBundle() {
  cv::Mat1b img(200, 400, uint8_t(255));
  const cv::Scalar black(0);
  cv::rectangle(img, cv::Point(20, 40), cv::Point(240, 120), black, 2);
  cv::rectangle(img, cv::Point(280, 40), cv::Point(380, 160), black, 2);
  efs::prior_map::SketchLoadConfig lc;
  lc.scale_guess_m_per_px = 0.1;
  efs::prior_map::PriorMapConfig config;
  config.guidepoints.mapping_range_m = 3.0;
  return efs::prior_map::buildPriorBundle(efs::prior_map::sketchFromImage(img, lc, "two_rooms"),
                                          config);
}

TEST(PriorFromBundle, GuidepointsAndPrmDistancesCarryOver) {
  const efs::prior_map::PriorBundle b = twoRoomBundle();
  const GuidepointPrior p = guidepointPriorFromBundle(b);
  ASSERT_GE(p.size(), 3);
  ASSERT_EQ(p.size(), static_cast<int>(b.guidepoints.size()));
  bool some_unreachable = false, some_reachable = false;
  for (int i = 0; i < p.size(); ++i) {
    EXPECT_EQ(p.ids[i], b.guidepoints[i].id);
    EXPECT_TRUE(p.positions_sketch_m[i].isApprox(b.guidepoints[i].position_m));
    EXPECT_TRUE(b.frame.contains(p.positions_sketch_m[i]));
    for (int j = 0; j < p.size(); ++j) {
      if (!b.distances.reachable(i, j)) {
        EXPECT_EQ(p.prm_distance_m(i, j), kUnreachable);
        some_unreachable = true;
        EXPECT_NE(b.guidepoints[i].component, b.guidepoints[j].component);
      } else {
        EXPECT_DOUBLE_EQ(p.prm_distance_m(i, j), b.distances.at(i, j));
        // A path is never shorter than the straight line (sketch metres on both sides).
        EXPECT_GE(p.prm_distance_m(i, j) + 1e-6,
                  (p.positions_sketch_m[i] - p.positions_sketch_m[j]).norm());
        some_reachable = some_reachable || i != j;
      }
    }
  }
  EXPECT_TRUE(some_unreachable) << "the two rooms have no door: some pair must be unreachable";
  EXPECT_TRUE(some_reachable);
  EXPECT_NO_THROW(p.validate());
}

TEST(PriorFromBundle, PredictedFreeSamplesCoverTheTraversableArea) {
  const efs::prior_map::PriorBundle b = twoRoomBundle();
  const GuidepointPrior p = guidepointPriorFromBundle(b, 1.0);
  ASSERT_FALSE(p.predicted_free_sketch_m.empty());
  EXPECT_NEAR(p.predicted_free_cell_m, 1.0, 1e-9);  // 10 px of 0.1 m
  for (const Eigen::Vector2d& s : p.predicted_free_sketch_m) {
    const Eigen::Vector2d px = b.frame.toPixel(s);
    EXPECT_NE(b.traversable(static_cast<int>(px.y()), static_cast<int>(px.x())), 0);
  }
  const double area_m2 = cv::countNonZero(b.traversable) * b.frame.m_per_px * b.frame.m_per_px;
  const double sampled_m2 =
      p.predicted_free_sketch_m.size() * p.predicted_free_cell_m * p.predicted_free_cell_m;
  EXPECT_NEAR(sampled_m2, area_m2, 0.15 * area_m2);
  EXPECT_THROW(guidepointPriorFromBundle(b, 0.0), std::invalid_argument);
  EXPECT_THROW(guidepointPriorFromBundle(b, std::nan("")), std::invalid_argument);
}

TEST(PriorFromBundle, MismatchedDistanceMatrixIsRefused) {
  efs::prior_map::PriorBundle b = twoRoomBundle();
  b.distances = efs::prior_map::DistanceMatrix(1);
  EXPECT_THROW(guidepointPriorFromBundle(b), std::invalid_argument);
}

}  // namespace
}  // namespace efs::planner
