// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The first seconds of a real building's flight, closed loop: the simulator, the exploration
// planner and the local planner as explore_mission runs them.
#include <gtest/gtest.h>

#include "efs_common/testing/paths.h"
#include "exploration_mission/mission_spec.h"

namespace efs::mission {
namespace {

// ed21 imported at 0.1 m voxels (as the exploration benchmark does) starts the vehicle in a
// small room whose door opens onto a corridor. Seen from there, no place behind the door holds a
// 0.5 m known-free ball: the opening had no viewpoint, and the exploration "finished" on its
// first plan, at 0.1 s with 2.2 % coverage. With the narrow clearance for openings it leaves.
TEST(MissionStart, TheEd21FlightLeavesItsStartRoom) {
  MissionSpec spec;
  spec.world.sdf_path = testing::sharedDataPath("ed21/ed21.world");
  spec.world.resolution_m = 0.1;
  spec.method = "prior_free";
  MissionConfig config;
  config.time_limit_s = 12.0;
  const std::unique_ptr<ExplorationMission> mission = makeMission(spec, config);
  const MissionLog& log = mission->run();
  EXPECT_STREQ(toString(log.end), toString(MissionEnd::kTimeLimit)) << log.end_message;
  EXPECT_GT(log.flight_distance_m, 10.0);
  EXPECT_GT(log.coverage, 0.1);
}

}  // namespace
}  // namespace efs::mission
