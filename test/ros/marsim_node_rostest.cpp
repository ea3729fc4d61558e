// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// marsim_node: drives /clock, publishes FAST-LIO2-shaped odometry and clouds, hovers under a
// hover SO3 command, refuses a NaN command (reported in sim_status, vehicle keeps hovering), and
// refuses a bad world with one clear line.
#include <explore_from_sketch/SO3Command.h>
#include <explore_from_sketch/SimulatorStatus.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/transform_listener.h>

#include <cmath>

#include "ros_test_utils.h"

namespace {

using efs::rostest::waitForMessage;

// Hover: thrust = m g straight up, level attitude.
explore_from_sketch::SO3Command hoverCommand(double mass_kg) {
  explore_from_sketch::SO3Command c;
  c.force.z = mass_kg * 9.81;
  c.orientation.w = 1.0;
  c.kR = {1.5, 1.5, 1.0};
  c.kOm = {0.13, 0.13, 0.1};
  return c;
}

TEST(MarsimNode, PublishesClockOdometryAndClouds) {
  ros::NodeHandle nh;
  const auto odom = waitForMessage<nav_msgs::Odometry>(nh, "Odometry", 60.0);
  ASSERT_TRUE(odom) << "no Odometry";
  EXPECT_EQ(odom->header.frame_id, "camera_init");
  EXPECT_EQ(odom->child_frame_id, "body");
  EXPECT_TRUE(efs::rostest::waitForSimTime(5.0)) << "no /clock";
  const auto cloud = waitForMessage<sensor_msgs::PointCloud2>(nh, "cloud_registered", 10.0);
  ASSERT_TRUE(cloud);
  EXPECT_GT(cloud->width, 1000u);  // ~20k returns per 10 Hz frame, minus misses
  const auto status = waitForMessage<explore_from_sketch::SimulatorStatus>(nh, "sim_status", 10.0);
  ASSERT_TRUE(status);
  EXPECT_GT(status->coverage, 0.0);
  EXPECT_LE(status->coverage, 1.0);
  // The pose is on TF too, as FAST-LIO2 broadcasts it.
  tf2_ros::Buffer buffer;
  tf2_ros::TransformListener listener(buffer);
  const auto tf = buffer.lookupTransform("camera_init", "body", ros::Time(0), ros::Duration(5.0));
  EXPECT_TRUE(std::isfinite(tf.transform.translation.z));
  EXPECT_NEAR(tf.transform.rotation.w * tf.transform.rotation.w +
                  tf.transform.rotation.z * tf.transform.rotation.z +
                  tf.transform.rotation.x * tf.transform.rotation.x +
                  tf.transform.rotation.y * tf.transform.rotation.y,
              1.0, 1e-6);
}

TEST(MarsimNode, HoversUnderCommandAndRefusesNan) {
  ros::NodeHandle nh;
  ros::Publisher cmd = nh.advertise<explore_from_sketch::SO3Command>("so3_cmd", 10);
  const auto start = waitForMessage<nav_msgs::Odometry>(nh, "ground_truth/odom", 30.0);
  ASSERT_TRUE(start);
  // QuadrotorConfig's default mass; a wrong force would make the vehicle climb or sink.
  const auto hover = hoverCommand(0.98);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(4.0);
  bool sent_nan = false;
  while (ros::WallTime::now() < end) {
    cmd.publish(hover);
    if (!sent_nan && ros::WallTime::now() > end - ros::WallDuration(2.0)) {
      auto bad = hover;
      bad.force.x = std::nan("");
      cmd.publish(bad);
      sent_nan = true;
    }
    ros::WallDuration(0.01).sleep();
  }
  const auto now = waitForMessage<nav_msgs::Odometry>(nh, "ground_truth/odom", 5.0);
  ASSERT_TRUE(now);
  const double dz = now->pose.pose.position.z - start->pose.pose.position.z;
  const double dx = now->pose.pose.position.x - start->pose.pose.position.x;
  EXPECT_LT(std::abs(dz), 0.5) << "did not hold altitude";
  EXPECT_LT(std::abs(dx), 0.5);
  const auto status = waitForMessage<explore_from_sketch::SimulatorStatus>(nh, "sim_status", 5.0);
  ASSERT_TRUE(status);
  EXPECT_GE(status->rejected_commands, 1u);
  EXPECT_FALSE(status->last_rejection.empty());
  EXPECT_FALSE(status->collided);
}

TEST(MarsimNode, BadWorldStopsCleanly) {
  const auto run =
      efs::rostest::runNode("marsim_node", "_world_kind:=castle _publish_clock:=false", 60);
  EXPECT_NE(run.exit_code, 0);
  EXPECT_LT(run.exit_code, 128) << run.output;
  EXPECT_NE(run.output.find("world_kind"), std::string::npos) << run.output;
}

TEST(MarsimNode, MissingWorldFileStopsCleanly) {
  const auto run = efs::rostest::runNode(
      "marsim_node", "_world_sdf:=/nonexistent.world _publish_clock:=false", 60);
  EXPECT_NE(run.exit_code, 0);
  EXPECT_LT(run.exit_code, 128) << run.output;
  EXPECT_NE(run.output.find("nonexistent.world"), std::string::npos) << run.output;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "marsim_node_rostest");
  return RUN_ALL_TESTS();
}
