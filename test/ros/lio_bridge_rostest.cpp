// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// lio_bridge_node driven with FAST-LIO2-shaped messages: odometry without twist gains a velocity
// estimate, clouds come out in the world frame, registration frames carry the robot position and
// the local map, and bad input (NaN pose, cloud without xyz, silence) is reported without the
// node stopping.
#include <explore_from_sketch/LioStatus.h>
#include <explore_from_sketch/RegistrationFrame.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <thread>

#include <iterator>
#include <map>
#include "efs_common_ros/cloud_conversions.h"

#include "ros_test_utils.h"

namespace {

class LioBridgeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    odom_pub_ = nh_.advertise<nav_msgs::Odometry>("/Odometry", 10);
    cloud_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("/cloud_registered", 10);
    odom_sub_ = nh_.subscribe("odom", 10, &LioBridgeTest::onOdom, this);
    frame_sub_ = nh_.subscribe("registration_frame", 10, &LioBridgeTest::onFrame, this);
    status_sub_ = nh_.subscribe("lio_status", 10, &LioBridgeTest::onStatus, this);
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
    while ((odom_pub_.getNumSubscribers() == 0 || cloud_pub_.getNumSubscribers() == 0) &&
           ros::WallTime::now() < end) {
      ros::WallDuration(0.05).sleep();
    }
  }

  // Flies along +x at 1 m/s for `seconds`, odometry at 50 Hz and a wall cloud at 10 Hz.
  void fly(double seconds) {
    const ros::WallTime start = ros::WallTime::now();
    int i = 0;
    while ((ros::WallTime::now() - start).toSec() < seconds) {
      const ros::Time stamp = ros::Time::now();
      x_ += 0.02;
      nav_msgs::Odometry o;
      o.header.stamp = stamp;
      o.header.frame_id = "camera_init";
      o.pose.pose.position.x = x_;
      o.pose.pose.position.z = 1.0;
      o.pose.pose.orientation.w = 1.0;
      odom_pub_.publish(o);
      published_x_[stamp.toNSec()] = x_;
      if (i++ % 5 == 0) {
        std::vector<Eigen::Vector3f> wall;
        for (int k = 0; k < 200; ++k)
          wall.emplace_back(static_cast<float>(x_ + 0.1 * k - 10.0), 3.0f, 1.0f);
        std_msgs::Header h;
        h.stamp = stamp;
        h.frame_id = "camera_init";
        cloud_pub_.publish(efs::ros_common::toPointCloud2(wall, h));
      }
      ros::spinOnce();
      ros::WallDuration(0.02).sleep();
    }
  }

  void spinFor(double seconds) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::WallTime::now() < end) {
      ros::spinOnce();
      ros::WallDuration(0.01).sleep();
    }
  }

  void onOdom(const nav_msgs::Odometry& m) {
    last_odom_ = m;
    ++odom_count_;
  }
  void onFrame(const explore_from_sketch::RegistrationFrame& m) {
    last_frame_ = m;
    ++frame_count_;
  }
  void onStatus(const explore_from_sketch::LioStatus& m) { last_status_ = m; }

  ros::NodeHandle nh_;
  ros::Publisher odom_pub_, cloud_pub_;
  ros::Subscriber odom_sub_, frame_sub_, status_sub_;
  double x_ = 0.0;
  std::map<uint64_t, double> published_x_;  ///< odometry x by stamp [ns]
  nav_msgs::Odometry last_odom_;
  explore_from_sketch::RegistrationFrame last_frame_;
  explore_from_sketch::LioStatus last_status_;
  int odom_count_ = 0, frame_count_ = 0;
};

TEST_F(LioBridgeTest, OdometryGainsVelocityAndFramesCarryTheMap) {
  fly(3.0);
  ASSERT_GT(odom_count_, 50);
  EXPECT_EQ(last_odom_.header.frame_id, "world");
  EXPECT_EQ(last_odom_.child_frame_id, "base_link");
  EXPECT_NEAR(last_odom_.twist.twist.linear.x, 1.0, 0.2);
  EXPECT_NEAR(last_odom_.twist.twist.linear.y, 0.0, 0.1);
  EXPECT_GE(frame_count_, 4);  // 2 Hz for 3 s
  EXPECT_GT(last_frame_.local_map.width, 50u);
  // The frame carries the robot position of its own time (frames are 0.5 s apart; the robot
  // moves on): the odometry published at or just before the frame's stamp.
  const auto at = published_x_.upper_bound(last_frame_.header.stamp.toNSec());
  ASSERT_NE(at, published_x_.begin()) << "frame stamped before any odometry";
  EXPECT_NEAR(last_frame_.robot_position.x, std::prev(at)->second, 0.05);
  EXPECT_EQ(last_status_.health, explore_from_sketch::LioStatus::HEALTHY);
}

TEST_F(LioBridgeTest, BadInputIsReportedAndTheNodeKeepsRunning) {
  fly(0.5);
  nav_msgs::Odometry nan;
  nan.header.stamp = ros::Time::now();
  nan.pose.pose.position.x = std::nan("");
  nan.pose.pose.orientation.w = 1.0;
  odom_pub_.publish(nan);
  spinFor(0.5);
  EXPECT_NE(last_status_.last_problem.find("non-finite"), std::string::npos)
      << last_status_.last_problem;

  sensor_msgs::PointCloud2 no_xyz;
  no_xyz.header.stamp = ros::Time::now();
  no_xyz.width = 3;
  no_xyz.height = 1;
  cloud_pub_.publish(no_xyz);
  spinFor(0.5);
  EXPECT_NE(last_status_.last_problem.find("no float32 field"), std::string::npos)
      << last_status_.last_problem;
  EXPECT_GT(last_status_.rejected_count, 0u);

  // Silence: the input goes stale; then it recovers.
  spinFor(1.0);
  EXPECT_EQ(last_status_.health, explore_from_sketch::LioStatus::STALE);
  const int before = odom_count_;
  fly(0.5);
  EXPECT_GT(odom_count_, before + 10);
  spinFor(0.15);
  EXPECT_EQ(last_status_.health, explore_from_sketch::LioStatus::HEALTHY);
  EXPECT_TRUE(efs::rostest::nodeAlive("/lio_bridge"));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "lio_bridge_rostest");
  return RUN_ALL_TESTS();
}
