// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// sim_explore.launch, every node really started: the simulator's LIO-shaped output goes through
// lio_bridge, registration and planner to the trajectory server and controller, whose commands
// fly the simulated vehicle. After 40 s of simulated flight the vehicle has moved through the
// cave without touching it, coverage has grown, and every stage has spoken.
#include <explore_from_sketch/ExplorationStatus.h>
#include <explore_from_sketch/PositionCommand.h>
#include <explore_from_sketch/RegistrationHypotheses.h>
#include <explore_from_sketch/SO3Command.h>
#include <explore_from_sketch/SimulatorStatus.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>

#include "ros_test_utils.h"

namespace {

using efs::rostest::waitForMessage;

TEST(SimExplore, FliesAClosedLoopExploration) {
  ros::NodeHandle nh;
  // Every stage produces its output.
  ASSERT_TRUE(waitForMessage<nav_msgs::Odometry>(nh, "odom", 90.0)) << "lio_bridge: no odom";
  ASSERT_TRUE(waitForMessage<explore_from_sketch::ExplorationStatus>(nh, "exploration_status", 30))
      << "planner: no exploration_status";
  ASSERT_TRUE(waitForMessage<explore_from_sketch::PositionCommand>(nh, "position_cmd", 30))
      << "minco_traj: no position_cmd";
  ASSERT_TRUE(waitForMessage<explore_from_sketch::SO3Command>(nh, "so3_cmd", 30))
      << "se3_controller: no so3_cmd";
  ASSERT_TRUE(waitForMessage<explore_from_sketch::RegistrationHypotheses>(nh, "hypotheses", 60))
      << "sketch_registration: no hypotheses message";

  const auto first = waitForMessage<explore_from_sketch::SimulatorStatus>(nh, "sim_status", 10);
  ASSERT_TRUE(first);
  // Fly for 40 s of simulated time.
  boost::shared_ptr<const explore_from_sketch::SimulatorStatus> last = first;
  const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(150.0);
  while (last->sim_time < first->sim_time + 40.0 && ros::WallTime::now() < give_up) {
    auto s = waitForMessage<explore_from_sketch::SimulatorStatus>(nh, "sim_status", 10);
    ASSERT_TRUE(s) << "simulator stopped publishing";
    last = s;
    if (last->collided) break;
  }
  EXPECT_FALSE(last->collided) << "collision at (" << last->collision_position.x << ", "
                               << last->collision_position.y << ", " << last->collision_position.z
                               << ")";
  EXPECT_GE(last->sim_time, first->sim_time + 40.0) << "simulated time did not advance enough";
  EXPECT_GT(last->travelled_distance - first->travelled_distance, 10.0)
      << "the vehicle hardly moved";
  EXPECT_GT(last->coverage, first->coverage + 0.1) << "coverage did not grow";
  EXPECT_EQ(last->rejected_commands, 0u)
      << "the controller sent invalid commands: " << last->last_rejection;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "sim_explore_rostest");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
