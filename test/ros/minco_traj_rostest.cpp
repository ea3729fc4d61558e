// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// minco_traj_node with a perfectly tracking vehicle played by the test (odometry = the last
// commanded position): a target gives a PositionCommand stream at ~100 Hz that reaches it, the
// published PolynomialTrajectory reproduces the commands (message round trip), a wall seen in
// scan_world is avoided with clearance, and a NaN target is refused while the node keeps going.
#include <explore_from_sketch/PolynomialTrajectory.h>
#include <explore_from_sketch/PositionCommand.h>
#include <geometry_msgs/PointStamped.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>
#include <limits>
#include <map>

#include "efs_common_ros/cloud_conversions.h"
#include "minco_traj_ros/traj_messages.h"
#include "ros_test_utils.h"

namespace {

using explore_from_sketch::PolynomialTrajectory;
using explore_from_sketch::PositionCommand;

class MincoTrajNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    odom_pub_ = nh_.advertise<nav_msgs::Odometry>("odom", 10);
    scan_pub_ = nh_.advertise<sensor_msgs::PointCloud2>("scan_world", 2, true);
    target_pub_ = nh_.advertise<geometry_msgs::PoseStamped>("exploration_target", 2);
    cmd_sub_ = nh_.subscribe("position_cmd", 200, &MincoTrajNodeTest::onCmd, this);
    traj_sub_ = nh_.subscribe("trajectory", 20, &MincoTrajNodeTest::onTraj, this);
    marker_sub_ = nh_.subscribe("traj_markers", 5, &MincoTrajNodeTest::onMarkers, this);
    // rostest starts no rosout node, so /rosout_agg (what LogCollector reads) stays silent: the
    // collector reads the node's /rosout directly, through log_nh_. Its log lines only arrive once
    // /rosout of the node and of this test itself is connected.
    rosout_sub_ = nh_.subscribe("/rosout", 100, &MincoTrajNodeTest::onRosout, this);
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(20.0);
    while ((odom_pub_.getNumSubscribers() == 0 || target_pub_.getNumSubscribers() == 0 ||
            scan_pub_.getNumSubscribers() == 0 || rosout_sub_.getNumPublishers() < 2) &&
           ros::WallTime::now() < end)
      ros::WallDuration(0.05).sleep();
    ASSERT_GE(rosout_sub_.getNumPublishers(), 2u) << "/rosout of the node not connected";
  }

  void onCmd(const PositionCommand::ConstPtr& m) {
    cmds_.push_back(*m);
    p_ = {m->position.x, m->position.y, m->position.z};
  }
  void onTraj(const PolynomialTrajectory::ConstPtr& m) { trajs_[m->trajectory_id] = *m; }
  void onMarkers(const visualization_msgs::MarkerArray::ConstPtr& m) { markers_ = *m; }

  // Plays the vehicle for `seconds`: odometry at 100 Hz at the last commanded position.
  void fly(double seconds) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::WallTime::now() < end) {
      nav_msgs::Odometry o;
      o.header.stamp = ros::Time::now();
      o.header.frame_id = "world";
      o.pose.pose.position.x = p_.x();
      o.pose.pose.position.y = p_.y();
      o.pose.pose.position.z = p_.z();
      o.pose.pose.orientation.w = 1.0;
      odom_pub_.publish(o);
      ros::spinOnce();
      ros::WallDuration(0.01).sleep();
    }
  }

  void sendTarget(double x, double y, double z) {
    geometry_msgs::PoseStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = "world";
    t.pose.position.x = x;
    t.pose.position.y = y;
    t.pose.position.z = z;
    t.pose.orientation.w = 1.0;  // yaw 0
    target_pub_.publish(t);
  }

  void onRosout(const rosgraph_msgs::Log::ConstPtr&) {}  // only holds the /rosout connection

  ros::NodeHandle nh_;
  ros::NodeHandle log_nh_{"", ros::M_string{{"/rosout_agg", "/rosout"}}};
  ros::Publisher odom_pub_, scan_pub_, target_pub_;
  ros::Subscriber cmd_sub_, traj_sub_, marker_sub_, rosout_sub_;
  std::vector<PositionCommand> cmds_;
  std::map<uint32_t, PolynomialTrajectory> trajs_;
  visualization_msgs::MarkerArray markers_;
  Eigen::Vector3d p_{0.0, 0.0, 1.0};
};

std::vector<Eigen::Vector3f> wall() {
  std::vector<Eigen::Vector3f> pts;
  for (float y = -1.0f; y <= 1.0f; y += 0.05f)
    for (float z = 0.0f; z <= 2.0f; z += 0.05f) pts.emplace_back(2.5f, y, z);
  return pts;
}

TEST_F(MincoTrajNodeTest, FliesToTargetsAroundAWallAndRefusesNan) {
  fly(0.5);
  EXPECT_TRUE(cmds_.empty()) << "commands before any target";

  std_msgs::Header h;
  h.stamp = ros::Time::now();
  h.frame_id = "world";
  scan_pub_.publish(efs::ros_common::toPointCloud2(wall(), h));
  fly(0.5);
  const Eigen::Vector3d goal(5.0, 0.0, 1.0);
  sendTarget(goal.x(), goal.y(), goal.z());
  fly(2.0);
  ASSERT_FALSE(cmds_.empty()) << "no position_cmd after a target";
  // ~100 Hz (loose bounds: the test shares the CPU).
  const double span_s = (cmds_.back().header.stamp - cmds_.front().header.stamp).toSec();
  ASSERT_GT(span_s, 1.0);
  const double rate_hz = (cmds_.size() - 1) / span_s;
  EXPECT_GT(rate_hz, 60.0);
  EXPECT_LT(rate_hz, 140.0);
  fly(4.0);
  EXPECT_LT((p_ - goal).norm(), 0.05) << "did not reach the target: " << p_.transpose();
  EXPECT_EQ(cmds_.back().trajectory_flag, PositionCommand::TRAJECTORY_STATUS_COMPLETED);

  // Clearance from the wall all the way, and the commands reproduce the published trajectories.
  const auto pts = wall();
  double min_dist = 1e9, max_mismatch = 0.0;
  int checked = 0;
  for (const auto& c : cmds_) {
    const Eigen::Vector3d p(c.position.x, c.position.y, c.position.z);
    for (const auto& w : pts) min_dist = std::min(min_dist, (w.cast<double>() - p).norm());
    const auto it = trajs_.find(c.trajectory_id);
    if (it == trajs_.end()) continue;
    std::string why;
    const auto traj = efs::traj::fromPolynomialTrajectory(it->second, &why);
    ASSERT_TRUE(traj) << why;
    const double t = (c.header.stamp - it->second.header.stamp).toSec();
    if (t < 0.0) continue;  // the previous trajectory still runs until the switch
    max_mismatch = std::max(max_mismatch, (traj->position(t) - p).norm());
    ++checked;
  }
  EXPECT_GT(min_dist, 0.25);
  EXPECT_GT(checked, 100);
  EXPECT_LT(max_mismatch, 1e-6);
  EXPECT_FALSE(trajs_.empty());
  // Markers of the last plan: trajectory, corridor edges (line list), front-end path.
  std::map<std::string, const visualization_msgs::Marker*> by_ns;
  for (const auto& m : markers_.markers) by_ns[m.ns] = &m;
  ASSERT_TRUE(by_ns.count("trajectory") && by_ns.count("corridor") && by_ns.count("front_end"));
  EXPECT_GE(by_ns["trajectory"]->points.size(), 2u);
  EXPECT_EQ(by_ns["corridor"]->type, visualization_msgs::Marker::LINE_LIST);
  EXPECT_GE(by_ns["corridor"]->points.size(), 24u);  // at least one box-like polytope
  EXPECT_EQ(by_ns["corridor"]->points.size() % 2, 0u);

  // NaN target: refused, the node holds and keeps commanding.
  efs::rostest::LogCollector logs(log_nh_);
  sendTarget(std::numeric_limits<double>::quiet_NaN(), 0.0, 1.0);
  EXPECT_TRUE(logs.waitFor("/minco_traj", "target rejected", 5.0));
  const size_t before = cmds_.size();
  fly(0.5);
  EXPECT_GT(cmds_.size(), before + 20);
  EXPECT_LT((p_ - goal).norm(), 0.05);
  EXPECT_TRUE(efs::rostest::nodeAlive("/minco_traj"));

  // A goal under a floor that spans the whole window: no plan reaches it, and after
  // give_up_after_failed_plans attempts the node says so once on unreachable_goal (for the
  // exploration planner), and keeps commanding the hold.
  std::vector<geometry_msgs::PointStamped> given_up;
  ros::Subscriber unreachable_sub = nh_.subscribe<geometry_msgs::PointStamped>(
      "unreachable_goal", 5,
      [&given_up](const geometry_msgs::PointStamped::ConstPtr& m) { given_up.push_back(*m); });
  std::vector<Eigen::Vector3f> floor;
  for (float x = -10.0f; x <= 20.0f; x += 0.1f)
    for (float y = -15.0f; y <= 15.0f; y += 0.1f) floor.emplace_back(x, y, 0.0f);
  h.stamp = ros::Time::now();
  scan_pub_.publish(efs::ros_common::toPointCloud2(floor, h));
  fly(1.0);
  const Eigen::Vector3d below(8.0, 0.0, -1.5);
  sendTarget(below.x(), below.y(), below.z());
  const size_t cmds_before = cmds_.size();
  fly(6.0);
  ASSERT_EQ(given_up.size(), 1u) << "no (or more than one) unreachable_goal for one goal";
  EXPECT_EQ(given_up[0].header.frame_id, "world");
  EXPECT_NEAR(given_up[0].point.x, below.x(), 1e-9);
  EXPECT_NEAR(given_up[0].point.y, below.y(), 1e-9);
  EXPECT_NEAR(given_up[0].point.z, below.z(), 1e-9);
  EXPECT_TRUE(logs.waitFor("/minco_traj", "giving up on the goal", 3.0));
  EXPECT_GT(cmds_.size(), cmds_before + 300);
  EXPECT_GT(p_.z(), 0.5) << "went through the floor";
  EXPECT_TRUE(efs::rostest::nodeAlive("/minco_traj"));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "minco_traj_rostest");
  return RUN_ALL_TESTS();
}
