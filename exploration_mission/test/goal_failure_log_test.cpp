// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/goal_failure_log.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "efs_common/testing/text_lines.h"

namespace efs::mission {
namespace {

TEST(GoalFailureLog, OneLinePerGoalWithPlacesStatusAndTheQuotedReason) {
  GoalFailureRecord refused;
  refused.time_s = 12.5;
  refused.goal_world_m = Eigen::Vector3d(257.5, 38.5, 40.5);
  refused.viewpoint_world_m = Eigen::Vector3d(258.25, 38.5, 40.25);
  refused.robot_world_m = Eigen::Vector3d(255.75, 39.25, 43.25);
  refused.failed_plans = 3;
  refused.status = traj::PlanStatus::kGoalUnreachable;
  refused.message = R"(goal in an occupied cell, "inflated")";
  refused.outcome = planner::GoalRefusal::kCountedReached;
  GoalFailureRecord stale = refused;
  stale.time_s = 20.0;
  stale.status = traj::PlanStatus::kCorridorFailed;
  stale.message = "no corridor";
  stale.outcome = planner::GoalRefusal::kNotCurrent;

  std::ostringstream out;
  writeGoalFailureLog(out, {refused, stale});
  const std::vector<std::string> l = testing::textLines(out.str());
  ASSERT_EQ(l.size(), 3u);
  EXPECT_EQ(l[0],
            "time_s,goal_x_m,goal_y_m,goal_z_m,viewpoint_x_m,viewpoint_y_m,viewpoint_z_m,robot_x_m,"
            "robot_y_m,robot_z_m,failed_plans,status,outcome,message");
  EXPECT_EQ(l[1], std::string("12.5,257.5,38.5,40.5,258.25,38.5,40.25,255.75,39.25,43.25,3,") +
                      traj::toString(traj::PlanStatus::kGoalUnreachable) +
                      R"(,counted_reached,"goal in an occupied cell, ""inflated""")");
  EXPECT_EQ(l[2], std::string("20,257.5,38.5,40.5,258.25,38.5,40.25,255.75,39.25,43.25,3,") +
                      traj::toString(traj::PlanStatus::kCorridorFailed) +
                      R"(,not_current,"no corridor")");
}

}  // namespace
}  // namespace efs::mission
