// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Stretches of real-building flights that ended early, closed loop: the simulator, the
// exploration planner and the local planner as explore_mission runs them.
#include <gtest/gtest.h>

#include <string>

#include "efs_common/testing/paths.h"
#include "exploration_mission/mission_report.h"
#include "exploration_mission/mission_spec.h"

namespace efs::mission {
namespace {

// ed21 imported at 0.1 m voxels, as the exploration benchmark does.
MissionSpec ed21At10cm(const std::string& method) {
  MissionSpec spec;
  spec.world.sdf_path = testing::sharedDataPath("ed21/ed21.world");
  spec.world.resolution_m = 0.1;
  spec.method = method;
  return spec;
}

// At 0.1 m, ed21 starts the vehicle in a small room whose door opens onto a corridor. Seen
// from there, no place behind the door holds a 0.5 m known-free ball: the opening had no viewpoint,
// and the exploration "finished" on its first plan, at 0.1 s with 2.2 % coverage. With the narrow
// clearance for openings it leaves.
TEST(MissionStart, TheEd21FlightLeavesItsStartRoom) {
  const MissionSpec spec = ed21At10cm("prior_free");
  MissionConfig config;
  config.time_limit_s = 12.0;
  const std::unique_ptr<ExplorationMission> mission = makeMission(spec, config);
  const MissionLog& log = mission->run();
  EXPECT_STREQ(toString(log.end), toString(MissionEnd::kTimeLimit)) << log.end_message;
  EXPECT_GT(log.flight_distance_m, 10.0);
  EXPECT_GT(log.coverage, 0.1);
}

// The ed21 flight with sketch_ed21_1.png (0.1 m import) enters the west room at 103-105 s
// through the 1.0-1.1 m mouth of a corridor. From the room the exploration planner's 0.6 m
// lattice reached no viewpoint: all 21 were "unreachable" in two plans 0.1 s apart, given up,
// and the flight finished at 105.6 s with 78 % coverage. The robot's paths are now searched
// again on a 0.3 m lattice when the 0.6 m one reaches nothing (fine_path_resolution_factor).
TEST(MissionStart, TheEd21FlightWithSketch1LeavesTheWestRoom) {
  MissionSpec spec = ed21At10cm("proposed");
  spec.sketch_path = testing::sharedDataPath("ed21/sketch_ed21_1.png");
  spec.scale_guess_m_per_px = 0.1;
  MissionConfig config;
  config.time_limit_s = 125.0;
  ASSERT_EQ(config.exploration.fine_path_resolution_factor, 2);  // 1 fails: 21 given up at 105.6 s
  const std::unique_ptr<ExplorationMission> mission = makeMission(spec, config);
  const MissionLog& log = mission->run();
  EXPECT_STREQ(toString(log.end), toString(MissionEnd::kTimeLimit)) << log.end_message;
  EXPECT_EQ(mission->explorationManager().inputStats().viewpoints_given_up, 0u);
  // The benchmark's trajectory picture of this flight: the world and the sketch side by side.
  const cv::Mat panel = renderTrajectoryPanel(*mission);
  ASSERT_EQ(panel.type(), CV_8UC3);
  EXPECT_GE(panel.rows, 400);
  EXPECT_GT(panel.cols, panel.rows);
}

}  // namespace
}  // namespace efs::mission
