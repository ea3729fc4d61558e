// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// se3_controller_node (two instances: SO3Command output, and AttitudeTarget output in the
// namespace px4) fed odometry and position commands by the test: nothing is commanded before
// the first odometry; hover gives thrust m g and a
// level attitude (normalised hover throttle on AttitudeTarget); stale odometry keeps commands
// coming, level, near m g (height held before any descent); a NaN command is refused and the vehicle hovers; without
// commands it hovers where it is.
#include <explore_from_sketch/AttitudeTarget.h>
#include <explore_from_sketch/PositionCommand.h>
#include <explore_from_sketch/SO3Command.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "ros_test_utils.h"

namespace {

using explore_from_sketch::AttitudeTarget;
using explore_from_sketch::PositionCommand;
using explore_from_sketch::SO3Command;

constexpr double kMassKg = 0.98, kG = 9.81;

class Se3ControllerNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    odom_pub_ = nh_.advertise<nav_msgs::Odometry>("odom", 10);
    cmd_pub_ = nh_.advertise<PositionCommand>("position_cmd", 10);
    odom_px4_pub_ = nh_.advertise<nav_msgs::Odometry>("px4/odom", 10);
    cmd_px4_pub_ = nh_.advertise<PositionCommand>("px4/position_cmd", 10);
    so3_sub_ = nh_.subscribe("so3_cmd", 100, &Se3ControllerNodeTest::onSo3, this);
    att_sub_ = nh_.subscribe("px4/attitude_target", 100, &Se3ControllerNodeTest::onAtt, this);
    // rostest starts no rosout node, so /rosout_agg (what LogCollector reads) stays silent: the
    // collectors read the nodes' /rosout directly, through log_nh_. Their log lines only arrive
    // once /rosout of both nodes and of this test itself is connected.
    rosout_sub_ = nh_.subscribe("/rosout", 100, &Se3ControllerNodeTest::onRosout, this);
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(20.0);
    while ((odom_pub_.getNumSubscribers() == 0 || cmd_pub_.getNumSubscribers() == 0 ||
            odom_px4_pub_.getNumSubscribers() == 0 || so3_sub_.getNumPublishers() == 0 ||
            att_sub_.getNumPublishers() == 0 || rosout_sub_.getNumPublishers() < 3) &&
           ros::WallTime::now() < end)
      ros::WallDuration(0.05).sleep();
    ASSERT_GE(rosout_sub_.getNumPublishers(), 3u) << "/rosout of the nodes not connected";
  }

  void onSo3(const SO3Command::ConstPtr& m) { so3_.push_back(*m); }
  void onAtt(const AttitudeTarget::ConstPtr& m) { att_.push_back(*m); }

  // Publishes hover odometry at (0, 0, 1) (when `with_odom`) and a command at `cmd_z` for
  // `seconds` at 100 Hz.
  void run(double seconds, bool with_odom, double cmd_z) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::WallTime::now() < end) {
      const ros::Time now = ros::Time::now();
      if (with_odom) {
        nav_msgs::Odometry o;
        o.header.stamp = now;
        o.header.frame_id = "world";
        o.pose.pose.position.z = 1.0;
        o.pose.pose.orientation.w = 1.0;
        odom_pub_.publish(o);
        odom_px4_pub_.publish(o);
      }
      PositionCommand c;
      c.header.stamp = now;
      c.position.z = cmd_z;
      cmd_pub_.publish(c);
      cmd_px4_pub_.publish(c);
      ros::spinOnce();
      ros::WallDuration(0.01).sleep();
    }
  }

  static double tiltRad(const geometry_msgs::Quaternion& q) {
    const Eigen::Quaterniond e(q.w, q.x, q.y, q.z);
    return std::acos(std::min(1.0, (e.normalized() * Eigen::Vector3d::UnitZ()).z()));
  }

  void onRosout(const rosgraph_msgs::Log::ConstPtr&) {}  // only holds the /rosout connection

  ros::NodeHandle nh_;
  ros::NodeHandle log_nh_{"", ros::M_string{{"/rosout_agg", "/rosout"}}};
  ros::Publisher odom_pub_, cmd_pub_, odom_px4_pub_, cmd_px4_pub_;
  ros::Subscriber so3_sub_, att_sub_, rosout_sub_;
  std::vector<SO3Command> so3_;
  std::vector<AttitudeTarget> att_;
};

TEST_F(Se3ControllerNodeTest, HoverStaleOdometryAndNanCommand) {
  // Before any odometry the node says nothing: a command "motors off" sent to a vehicle that is
  // already in the air (a simulator starting in hover, a node restarted in flight) drops it.
  {
    efs::rostest::LogCollector logs(log_nh_);
    run(0.6, false, 1.0);
    EXPECT_TRUE(so3_.empty()) << so3_.size() << " SO3 commands before any odometry";
    EXPECT_TRUE(att_.empty()) << att_.size() << " attitude targets before any odometry";
    EXPECT_TRUE(logs.waitFor("/se3_controller", "no valid odometry yet", 5.0));
  }
  run(1.0, true, 1.0);
  ASSERT_GT(so3_.size(), 50u);
  ASSERT_GT(att_.size(), 50u);
  const SO3Command hover = so3_.back();
  EXPECT_NEAR(hover.force.z, kMassKg * kG, 0.05);
  EXPECT_NEAR(hover.force.x, 0.0, 1e-6);
  EXPECT_LT(tiltRad(hover.orientation), 1e-6);
  EXPECT_TRUE(hover.aux.enable_motors);
  EXPECT_NEAR(att_.back().thrust, 0.5, 0.05);  // hover_throttle_initial, no IMU
  EXPECT_LT(tiltRad(att_.back().orientation), 1e-6);
  // Error sign: a command above the vehicle pushes harder.
  run(0.3, true, 1.5);
  EXPECT_GT(so3_.back().force.z, kMassKg * kG + 1.0);

  // Odometry stops: the watchdog keeps commanding, level, holding the height (the descent
  // only starts after descent_delay_s), never a fall.
  efs::rostest::LogCollector logs(log_nh_);
  so3_.clear();
  run(0.8, false, 1.0);
  ASSERT_GT(so3_.size(), 30u) << "no commands while odometry is missing";
  EXPECT_LT(tiltRad(so3_.back().orientation), 0.05);
  EXPECT_LT(so3_.back().force.z, kMassKg * (kG + 1.0));
  EXPECT_GT(so3_.back().force.z, kMassKg * (kG - 1.0));
  EXPECT_TRUE(logs.waitFor("/se3_controller", "stale", 5.0));

  // Odometry back, then a NaN command: refused, hover at the latched position. Just before, a
  // short odometry gap (stale after 0.2 s) makes a stale-odometry warning: it must not hide the
  // hold warning that follows it within the same half second.
  run(0.5, true, 1.0);
  run(0.3, false, 1.0);
  so3_.clear();
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(0.6);
  while (ros::WallTime::now() < end) {
    nav_msgs::Odometry o;
    o.header.stamp = ros::Time::now();
    o.pose.pose.position.z = 1.0;
    o.pose.pose.orientation.w = 1.0;
    odom_pub_.publish(o);
    PositionCommand c;
    c.header.stamp = o.header.stamp;
    c.position.z = 1.0;
    c.position.x = std::numeric_limits<double>::quiet_NaN();
    cmd_pub_.publish(c);
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  ASSERT_GT(so3_.size(), 20u);
  for (const auto& c : so3_) {
    ASSERT_TRUE(std::isfinite(c.force.x) && std::isfinite(c.force.z) &&
                std::isfinite(c.orientation.w));
  }
  EXPECT_NEAR(so3_.back().force.z, kMassKg * kG, 0.05);
  EXPECT_LT(tiltRad(so3_.back().orientation), 1e-6);
  EXPECT_TRUE(logs.waitFor("/se3_controller", "hold_position: reference rejected", 5.0));

  // Commands stop, odometry goes on: hover where the vehicle is.
  run(0.5, true, 1.0);
  so3_.clear();
  const ros::WallTime quiet_end = ros::WallTime::now() + ros::WallDuration(1.0);
  while (ros::WallTime::now() < quiet_end) {
    nav_msgs::Odometry o;
    o.header.stamp = ros::Time::now();
    o.pose.pose.position.z = 1.0;
    o.pose.pose.orientation.w = 1.0;
    odom_pub_.publish(o);
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  ASSERT_GT(so3_.size(), 50u);
  EXPECT_NEAR(so3_.back().force.z, kMassKg * kG, 0.05);
  EXPECT_LT(tiltRad(so3_.back().orientation), 1e-6);
  EXPECT_TRUE(logs.waitFor("/se3_controller", "reference stale", 5.0));
  EXPECT_TRUE(efs::rostest::nodeAlive("/se3_controller"));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "se3_controller_rostest");
  return RUN_ALL_TESTS();
}
