// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The closed loop on a loaded onboard computer, as the ROS graph runs it there: the planner's
// target updated by its 2 Hz timer, its scans arriving late behind the odometry.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "efs_common/testing/config_error.h"
#include "exploration_mission/mission_spec.h"

namespace efs::mission {
namespace {

// The small cave with the deformed sketch (rostest.mission_lio_dropout's flight). Timed like a
// node held to 2 Hz (plan_rate_hz 2, a fifth of its default) with each scan 0.6 s late, it still
// explores the cave to the goal.
TEST(MissionTiming, ALatePlannerOnItsTimerStillExploresTheSmallCave) {
  MissionSpec spec;
  spec.world.kind = "simple_cave";
  MissionConfig config;
  config.time_limit_s = 120.0;
  config.planner_update_rate_hz = 2.0;
  config.planner_scan_latency_s = 0.6;
  const std::unique_ptr<ExplorationMission> mission = makeMission(spec, config);
  const MissionLog& log = mission->run();
  EXPECT_STREQ(toString(log.end), toString(MissionEnd::kExplorationComplete)) << log.end_message;
  EXPECT_GE(log.coverage, config.coverage_goal);
}

TEST(MissionTiming, BadTimingValuesNameTheirKey) {
  MissionConfig c;
  c.planner_scan_latency_s = -0.1;
  efs::testing::expectConfigErrorNaming([&] { c.validate(); }, "planner_scan_latency_s");
  c = {};
  c.planner_update_rate_hz = std::nan("");
  efs::testing::expectConfigErrorNaming([&] { c.validate(); }, "planner_update_rate_hz");
}

}  // namespace
}  // namespace efs::mission
