// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// replay.launch on a bag recorded by record_flight: the recorded FAST-LIO2 topics come back out
// of rosbag play on the bag's clock and drive lio_bridge, the registration and the planner.
#include <explore_from_sketch/ExplorationStatus.h>
#include <explore_from_sketch/RegistrationFrame.h>
#include <explore_from_sketch/RegistrationHypotheses.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include "ros_test_utils.h"

namespace {

using efs::rostest::waitForMessage;

TEST(Replay, RecordedFlightDrivesTheStack) {
  ros::NodeHandle nh;
  const auto cloud = waitForMessage<sensor_msgs::PointCloud2>(nh, "/cloud_registered", 30.0);
  ASSERT_TRUE(cloud) << "the bag is not being played";
  EXPECT_EQ(cloud->header.frame_id, "camera_init");
  EXPECT_GT(cloud->width * cloud->height, 1000u);
  const auto odom = waitForMessage<nav_msgs::Odometry>(nh, "odom", 10.0);
  ASSERT_TRUE(odom) << "lio_bridge: no odom from the replayed flight";
  EXPECT_EQ(odom->header.frame_id, "world");
  ASSERT_TRUE(waitForMessage<explore_from_sketch::RegistrationFrame>(nh, "registration_frame", 15))
      << "lio_bridge: no registration frame";
  const auto hyps =
      waitForMessage<explore_from_sketch::RegistrationHypotheses>(nh, "hypotheses", 20.0);
  ASSERT_TRUE(hyps) << "sketch_registration: no hypotheses message";
  const auto status =
      waitForMessage<explore_from_sketch::ExplorationStatus>(nh, "exploration_status", 20.0);
  ASSERT_TRUE(status) << "planner: no exploration_status";
  EXPECT_NE(status->state, explore_from_sketch::ExplorationStatus::STATE_FINISHED)
      << "the planner gave up on a flight that had only started";
  const auto target = waitForMessage<geometry_msgs::PoseStamped>(nh, "exploration_target", 20.0);
  ASSERT_TRUE(target) << "planner: no exploration target";
  EXPECT_TRUE(std::isfinite(target->pose.position.x));
  // The replay runs on the bag's clock.
  EXPECT_GT(ros::Time::now().toSec(), 0.0);
  EXPECT_LT(ros::Time::now().toSec(), 1000.0);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "replay_rostest");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
