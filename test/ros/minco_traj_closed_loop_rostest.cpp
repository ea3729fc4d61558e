// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The flight stack in the loop with the simulator: the test picks a free target a few metres
// away from the first scan (half-way along a roughly horizontal ray, so the straight line is
// known free), sends it to minco_traj_node and waits until the simulated vehicle, driven by
// se3_controller_node, holds there; no collision on the way.
#include <explore_from_sketch/PositionCommand.h>
#include <explore_from_sketch/SimulatorStatus.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include <Eigen/Core>
#include <optional>

#include "efs_common_ros/cloud_conversions.h"
#include "ros_test_utils.h"

namespace {

using efs::rostest::waitForMessage;

Eigen::Vector3d positionOf(const nav_msgs::Odometry& o) {
  return {o.pose.pose.position.x, o.pose.pose.position.y, o.pose.pose.position.z};
}

/// Half-way to the farthest return between 3 and 8 m whose ray is within 10 degrees of level.
std::optional<Eigen::Vector3d> freeTarget(const std::vector<Eigen::Vector3f>& cloud,
                                          const Eigen::Vector3d& sensor) {
  std::optional<Eigen::Vector3d> best;
  double best_range = 0.0;
  for (const auto& pf : cloud) {
    const Eigen::Vector3d d = pf.cast<double>() - sensor;
    const double r = d.norm();
    if (r < 3.0 || r > 8.0 || std::abs(d.z()) > 0.17 * r || r <= best_range) continue;
    best_range = r;
    best = sensor + 0.5 * d;
  }
  return best;
}

TEST(FlightStackClosedLoop, FliesToATargetWithoutCollision) {
  ros::NodeHandle nh;
  ros::Publisher target_pub = nh.advertise<geometry_msgs::PoseStamped>("exploration_target", 2);
  const auto odom0 = waitForMessage<nav_msgs::Odometry>(nh, "Odometry", 60.0);
  ASSERT_TRUE(odom0) << "no odometry from the simulator";
  const auto cloud = waitForMessage<sensor_msgs::PointCloud2>(nh, "cloud_registered", 30.0);
  ASSERT_TRUE(cloud);
  const Eigen::Vector3d start = positionOf(*odom0);
  const auto target = freeTarget(efs::ros_common::fromPointCloud2(*cloud), start);
  ASSERT_TRUE(target) << "no level return between 3 and 8 m in the first scan";
  ASSERT_GT((*target - start).norm(), 1.4);

  const ros::WallTime subs_end = ros::WallTime::now() + ros::WallDuration(20.0);
  while (target_pub.getNumSubscribers() == 0 && ros::WallTime::now() < subs_end)
    ros::WallDuration(0.05).sleep();
  geometry_msgs::PoseStamped t;
  t.header.stamp = ros::Time::now();
  t.header.frame_id = "camera_init";
  t.pose.position.x = target->x();
  t.pose.position.y = target->y();
  t.pose.position.z = target->z();
  target_pub.publish(t);  // all-zero orientation: look at the goal

  const auto cmd = waitForMessage<explore_from_sketch::PositionCommand>(nh, "position_cmd", 30.0);
  ASSERT_TRUE(cmd) << "no position_cmd after the target";
  // Up to 60 s of simulated time to get there and settle.
  double dist = 1e9;
  const ros::Time deadline = ros::Time::now() + ros::Duration(60.0);
  while (ros::Time::now() < deadline && ros::ok()) {
    const auto o = waitForMessage<nav_msgs::Odometry>(nh, "Odometry", 10.0);
    ASSERT_TRUE(o);
    dist = (positionOf(*o) - *target).norm();
    const double speed = std::hypot(o->twist.twist.linear.x, o->twist.twist.linear.y);
    if (dist < 0.15 && speed < 0.1) break;
    ros::WallDuration(0.1).sleep();
  }
  EXPECT_LT(dist, 0.15) << "the vehicle did not reach " << target->transpose();
  const auto status = waitForMessage<explore_from_sketch::SimulatorStatus>(nh, "sim_status", 10.0);
  ASSERT_TRUE(status);
  EXPECT_FALSE(status->collided);
  EXPECT_EQ(status->rejected_commands, 0u) << status->last_rejection;
  EXPECT_GT(status->travelled_distance, 0.8 * (*target - start).norm());
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "minco_traj_closed_loop_rostest");
  return RUN_ALL_TESTS();
}
