// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// prior_guided_planner_node driven with synthetic input: odometry inside a closed corridor room
// and full-sphere scans ray cast in it (world frame, like lio_bridge's scan_world). A target
// ahead in the corridor, the tour and the status arrive; bad input (NaN points, a cloud without
// xyz, a cloud in another frame, a hypothesis with NaN scale or a negative log_stretch, odometry
// back in time) is logged and the node keeps planning. With a sketch of the room and the right
// hypothesis the plan is prior-guided and the guidepoints carry states. Bad configuration stops the
// node at start-up.
#include <explore_from_sketch/ExplorationStatus.h>
#include <explore_from_sketch/Guidepoints.h>
#include <explore_from_sketch/RegistrationHypotheses.h>
#include <geometry_msgs/PointStamped.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <set>
#include <string>
#include <thread>

#include "../../prior_guided_planner/test/observation_map_test_scenes.h"
#include "efs_common_ros/cloud_conversions.h"
#include "prior_guided_planner_ros/planner_markers.h"
#include "prior_map_tools/prior_bundle.h"
#include "prior_map_tools/prior_map_builder.h"
#include "prior_map_tools/sketch_loader.h"
#include "ros_test_utils.h"

namespace {

using explore_from_sketch::ExplorationStatus;

constexpr const char* kNode = "/prior_guided_planner";

// What the node said, read from /rosout (where every node publishes its log lines; the
// aggregated /rosout_agg depends on the rosout node relaying them).
class RosoutCollector {
 public:
  explicit RosoutCollector(ros::NodeHandle& nh)
      : sub_(nh.subscribe("/rosout", 1000, &RosoutCollector::onLog, this)) {}
  bool waitFor(const std::string& node, const std::string& needle, double timeout_s) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    do {
      ros::spinOnce();
      for (const auto& m : logs_)
        if (m.name == node && m.msg.find(needle) != std::string::npos) return true;
      ros::WallDuration(0.05).sleep();
    } while (ros::WallTime::now() < end);
    return false;
  }
  size_t size() const { return logs_.size(); }

 private:
  void onLog(const rosgraph_msgs::Log& m) { logs_.push_back(m); }
  ros::Subscriber sub_;
  std::vector<rosgraph_msgs::Log> logs_;
};

class PlannerNodeTest : public ::testing::Test {
 protected:
  /// Namespace of the node under test ("" = the one the .test file launches).
  virtual std::string ns() const { return ""; }

  void SetUp() override {
    room_.room = {Eigen::Vector3d(0.15, -2.85, 0.15), Eigen::Vector3d(15.75, 3.15, 3.15)};
    odom_pub_ = nh_.advertise<nav_msgs::Odometry>(ns() + "/odom", 10);
    scan_pub_ = nh_.advertise<sensor_msgs::PointCloud2>(ns() + "/scan_world", 10);
    hyp_pub_ = nh_.advertise<explore_from_sketch::RegistrationHypotheses>(ns() + "/hypotheses", 10);
    target_sub_ = nh_.subscribe(ns() + "/exploration_target", 10, &PlannerNodeTest::onTarget, this);
    tour_sub_ = nh_.subscribe(ns() + "/exploration_tour", 10, &PlannerNodeTest::onTour, this);
    status_sub_ = nh_.subscribe(ns() + "/exploration_status", 10, &PlannerNodeTest::onStatus, this);
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(15.0);
    while ((odom_pub_.getNumSubscribers() == 0 || scan_pub_.getNumSubscribers() == 0 ||
            hyp_pub_.getNumSubscribers() == 0) &&
           ros::WallTime::now() < end) {
      ros::WallDuration(0.05).sleep();
    }
  }

  void publishOdom(const ros::Time& stamp) {
    nav_msgs::Odometry o;
    o.header.stamp = stamp;
    o.header.frame_id = "world";
    o.pose.pose.position.x = pos_.x();
    o.pose.pose.position.y = pos_.y();
    o.pose.pose.position.z = pos_.z();
    o.pose.pose.orientation.w = 1.0;
    odom_pub_.publish(o);
  }

  sensor_msgs::PointCloud2 scan(const std::string& frame) const {
    std::vector<Eigen::Vector3f> pts;
    for (const Eigen::Vector3d& p : room_.scanSphere(pos_, 2.0)) pts.push_back(p.cast<float>());
    std_msgs::Header h;
    h.stamp = ros::Time::now();
    h.frame_id = frame;
    return efs::ros_common::toPointCloud2(pts, h);
  }

  // Hovers at pos_ for `seconds`: odometry at 20 Hz, a scan at 5 Hz.
  void hover(double seconds) {
    const ros::WallTime start = ros::WallTime::now();
    int i = 0;
    while ((ros::WallTime::now() - start).toSec() < seconds) {
      publishOdom(ros::Time::now());
      if (i++ % 4 == 0) scan_pub_.publish(scan("world"));
      ros::spinOnce();
      ros::WallDuration(0.05).sleep();
    }
  }

  void spinFor(double seconds) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    while (ros::WallTime::now() < end) {
      ros::spinOnce();
      ros::WallDuration(0.01).sleep();
    }
  }

  void onTarget(const geometry_msgs::PoseStamped& m) {
    last_target_ = m;
    ++target_count_;
    const auto& p = m.pose.position;
    if (same_as_refused_ &&
        std::hypot(p.x - refused_.x, p.y - refused_.y, p.z - refused_.z) <= 1e-3)
      ++*same_as_refused_;
  }
  void onTour(const nav_msgs::Path& m) { last_tour_ = m; }
  void onStatus(const ExplorationStatus& m) {
    last_status_ = m;
    ++status_count_;
  }

  ros::NodeHandle nh_;
  efs::planner::testing::Scene room_;
  Eigen::Vector3d pos_{2.0, 0.1, 1.6};
  ros::Publisher odom_pub_, scan_pub_, hyp_pub_;
  ros::Subscriber target_sub_, tour_sub_, status_sub_;
  geometry_msgs::PoseStamped last_target_;
  nav_msgs::Path last_tour_;
  ExplorationStatus last_status_;
  int target_count_ = 0, status_count_ = 0;
  geometry_msgs::Point refused_;    ///< a goal that must not be sent again
  int* same_as_refused_ = nullptr;  ///< counts targets equal to refused_ while set
};

TEST_F(PlannerNodeTest, TargetTourAndStatusArrive) {
  spinFor(0.5);
  ASSERT_GT(status_count_, 0) << "status is published before any input";
  EXPECT_EQ(last_status_.state, ExplorationStatus::STATE_INIT);
  hover(2.0);
  spinFor(0.5);
  ASSERT_GT(target_count_, 0);
  EXPECT_EQ(last_target_.header.frame_id, "world");
  const auto& p = last_target_.pose.position;
  EXPECT_GT(p.x, pos_.x());  // the unexplored part of the corridor is ahead
  EXPECT_LT(p.x, 15.75);
  EXPECT_GT(p.y, -2.85);
  EXPECT_LT(p.y, 3.15);
  EXPECT_NEAR(std::hypot(last_target_.pose.orientation.z, last_target_.pose.orientation.w), 1.0,
              1e-6);
  ASSERT_GE(last_tour_.poses.size(), 2u);
  EXPECT_NEAR(last_tour_.poses[0].pose.position.x, pos_.x(), 1e-6);  // starts at the robot
  EXPECT_EQ(last_status_.state, ExplorationStatus::STATE_EXPLORING_PRIOR_FREE);
  EXPECT_FALSE(last_status_.has_active_hypothesis);
  EXPECT_GT(last_status_.remaining_viewpoints, 0u);
  EXPECT_GT(last_status_.coverage_estimate, 0.0);
  EXPECT_LE(last_status_.coverage_estimate, 1.0);
}

TEST_F(PlannerNodeTest, BadInputIsReportedAndTheNodeKeepsPlanning) {
  RosoutCollector logs(nh_);
  hover(1.0);

  // Some NaN points: dropped, counted, said.
  sensor_msgs::PointCloud2 nan_cloud;
  {
    std::vector<Eigen::Vector3f> pts;
    for (const Eigen::Vector3d& p : room_.scanSphere(pos_, 4.0)) pts.push_back(p.cast<float>());
    const float nan = std::numeric_limits<float>::quiet_NaN();
    pts.emplace_back(nan, 1.0f, 1.0f);
    pts.emplace_back(1.0f, nan, nan);
    std_msgs::Header h;
    h.stamp = ros::Time::now();
    h.frame_id = "world";
    nan_cloud = efs::ros_common::toPointCloud2(pts, h);
    // Scans are ray cast from the odometry at their stamp: one there, before the scan.
    publishOdom(h.stamp);
    ros::WallDuration(0.05).sleep();
  }
  scan_pub_.publish(nan_cloud);
  EXPECT_TRUE(logs.waitFor(kNode, "2 of", 3.0)) << logs.size() << " log lines seen";
  EXPECT_TRUE(logs.waitFor(kNode, "not finite", 0.1));

  // A cloud without x/y/z fields, and one in another frame: refused.
  sensor_msgs::PointCloud2 no_xyz;
  no_xyz.header.stamp = ros::Time::now();
  no_xyz.header.frame_id = "world";
  no_xyz.width = 3;
  no_xyz.height = 1;
  scan_pub_.publish(no_xyz);
  EXPECT_TRUE(logs.waitFor(kNode, "scan refused", 3.0));
  scan_pub_.publish(scan("camera_init"));
  EXPECT_TRUE(logs.waitFor(kNode, "camera_init", 3.0));
  // Stamped where no odometry is: its rays would start from a guess, so it is not used.
  sensor_msgs::PointCloud2 future = scan("world");
  future.header.stamp = ros::Time::now() + ros::Duration(5.0);
  scan_pub_.publish(future);
  EXPECT_TRUE(logs.waitFor(kNode, "sensor position at its stamp is unknown", 3.0));

  // A hypothesis with NaN scale: refused by name; the planner stays prior-free.
  explore_from_sketch::RegistrationHypotheses hyps;
  hyps.header.stamp = ros::Time::now();
  hyps.header.frame_id = "world";
  explore_from_sketch::RegistrationHypothesis h;
  h.id = 7;
  h.scale = std::nan("");
  h.confidence = 1.0;
  hyps.hypotheses.push_back(h);
  hyp_pub_.publish(hyps);
  EXPECT_TRUE(logs.waitFor(kNode, "hypothesis 7 refused", 3.0));
  // A negative log_stretch (a stretch below 1 is a shrink mislabelled): refused by name.
  hyps.hypotheses[0].id = 8;
  hyps.hypotheses[0].scale = 1.0;
  hyps.hypotheses[0].log_stretch = -0.1;
  hyp_pub_.publish(hyps);
  EXPECT_TRUE(logs.waitFor(kNode, "hypothesis 8 refused: stretch 0.90", 3.0));
  hyps.hypotheses[0].log_stretch = 0.0;
  hyps.header.frame_id = "camera_init";
  hyps.hypotheses[0].scale = 1.0;
  hyp_pub_.publish(hyps);
  EXPECT_TRUE(logs.waitFor(kNode, "hypotheses refused: they map into frame 'camera_init'", 3.0));

  // Odometry going back in time: refused.
  const ros::Time now = ros::Time::now();
  publishOdom(now);
  spinFor(0.2);
  publishOdom(now - ros::Duration(5.0));
  EXPECT_TRUE(logs.waitFor(kNode, "back in time", 3.0));

  // Silence: the odometry goes stale and the node says so instead of planning on it.
  spinFor(1.5);
  EXPECT_TRUE(logs.waitFor(kNode, "odometry is stale", 1.0));

  // Still alive and planning.
  const int targets = target_count_;
  const int statuses = status_count_;
  hover(1.5);
  spinFor(0.3);
  EXPECT_TRUE(efs::rostest::nodeAlive(kNode));
  EXPECT_GT(status_count_, statuses);
  EXPECT_GT(target_count_, targets);
  EXPECT_EQ(last_status_.state, ExplorationStatus::STATE_EXPLORING_PRIOR_FREE);
  EXPECT_FALSE(last_status_.has_active_hypothesis);
}

// minco_traj gave up on the current goal (unreachable_goal): the planner sets its viewpoint
// aside and sends another target; an unreachable goal in another frame, or a NaN one, is
// refused and said.
TEST_F(PlannerNodeTest, AGoalTheLocalPlannerGaveUpOnIsReplacedAtOnce) {
  RosoutCollector logs(nh_);
  ros::Publisher unreachable_pub =
      nh_.advertise<geometry_msgs::PointStamped>(ns() + "/unreachable_goal", 5);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
  while (unreachable_pub.getNumSubscribers() == 0 && ros::WallTime::now() < end)
    ros::WallDuration(0.05).sleep();
  ASSERT_GT(unreachable_pub.getNumSubscribers(), 0u);
  hover(2.0);
  ASSERT_GT(target_count_, 0);
  const geometry_msgs::Point refused = last_target_.pose.position;

  geometry_msgs::PointStamped m;
  m.header.stamp = ros::Time::now();
  m.header.frame_id = "camera_init";
  m.point = refused;
  unreachable_pub.publish(m);
  EXPECT_TRUE(logs.waitFor(kNode, "unreachable goal refused: frame 'camera_init'", 3.0));
  m.header.frame_id = "world";
  m.point.x = std::numeric_limits<double>::quiet_NaN();
  unreachable_pub.publish(m);
  EXPECT_TRUE(logs.waitFor(kNode, "unreachable goal refused: not finite", 3.0));

  m.point = refused;
  unreachable_pub.publish(m);
  EXPECT_TRUE(logs.waitFor(kNode, "gave up on", 3.0));
  spinFor(0.6);  // a target published before the report was handled may still be on its way
  const int targets_before = target_count_;
  int same = 0;
  refused_ = refused;
  same_as_refused_ = &same;
  hover(1.5);
  spinFor(0.3);
  same_as_refused_ = nullptr;
  EXPECT_EQ(same, 0) << "still sent the goal minco_traj gave up on";
  // Another target, or none left to go to (every viewpoint of this small room set aside).
  EXPECT_TRUE(target_count_ > targets_before ||
              last_status_.state == ExplorationStatus::STATE_EMERGENCY)
      << "state " << static_cast<int>(last_status_.state);
  EXPECT_TRUE(efs::rostest::nodeAlive(kNode));
}

// The corridor room drawn as a sketch (0.1 m per pixel, walls 2 px) and pre-processed; the
// hypothesis that puts it onto the room.
struct CorridorPrior {
  std::string path;
  explore_from_sketch::RegistrationHypothesis truth;
  size_t guidepoints = 0;
};

const CorridorPrior& corridorPrior() {
  static const CorridorPrior p = [] {
    namespace pm = efs::prior_map;
    cv::Mat1b img(100, 200, uint8_t(255));
    const cv::Point lo(20, 20), hi(176, 80);  // 15.6 m x 6 m inside
    cv::rectangle(img, lo, hi, cv::Scalar(0), 2);
    pm::SketchLoadConfig lc;
    lc.scale_guess_m_per_px = 0.1;
    pm::PriorMapConfig config;
    config.guidepoints.mapping_range_m = 2.0;
    const pm::PriorBundle b =
        pm::buildPriorBundle(pm::sketchFromImage(img, lc, "corridor"), config);
    CorridorPrior out;
    const char* dir = std::getenv("ROS_LOG_DIR");
    out.path = std::string(dir ? dir : "/tmp") + "/prior_guided_planner_rostest_corridor.prior";
    pm::savePriorBundle(b, out.path);
    out.guidepoints = b.guidepoints.size();
    // The sketch's lower-left inner corner goes to the room's (0.15, -2.85).
    const Eigen::Vector2d corner = b.frame.pixelCenter(lo.x, hi.y);
    out.truth.id = 3;
    out.truth.scale = 1.0;
    out.truth.tx = 0.15 - corner.x();
    out.truth.ty = -2.85 - corner.y();
    out.truth.confidence = 0.9;
    return out;
  }();
  return p;
}

// A second node with the corridor's prior in its own namespace (started by the test, stopped
// by `timeout` when its time is up).
class PriorPlannerNodeTest : public PlannerNodeTest {
 protected:
  std::string ns() const override { return "/with_prior"; }
  void SetUp() override {
    const std::string bundle = corridorPrior().path;
    node_ = std::thread([bundle] {
      efs::rostest::runNode("prior_guided_planner_node",
                            "__ns:=/with_prior _plan_rate_hz:=5.0 _replan_period_s:=0.2 "
                            "_prior_bundle_path:=" +
                                bundle,
                            25);
    });
    PlannerNodeTest::SetUp();
    guidepoints_sub_ =
        nh_.subscribe(ns() + "/guidepoints", 10, &PriorPlannerNodeTest::onGuidepoints, this);
    markers_sub_ =
        nh_.subscribe(ns() + "/planner_markers", 10, &PriorPlannerNodeTest::onMarkers, this);
  }
  void TearDown() override { node_.join(); }
  void onGuidepoints(const explore_from_sketch::Guidepoints& m) { last_guidepoints_ = m; }
  void onMarkers(const visualization_msgs::MarkerArray& m) {
    for (const auto& mk : m.markers)
      if (!mk.points.empty()) marker_ns_.insert(mk.ns);
  }

  std::thread node_;
  ros::Subscriber guidepoints_sub_, markers_sub_;
  std::set<std::string> marker_ns_;  ///< namespaces of non-empty markers received
  explore_from_sketch::Guidepoints last_guidepoints_;
};

TEST_F(PriorPlannerNodeTest, AHypothesisGuidesAndGuidepointsCarryStates) {
  ASSERT_GT(odom_pub_.getNumSubscribers(), 0u) << "the node with the prior did not start";
  hover(1.5);
  EXPECT_EQ(last_status_.state, ExplorationStatus::STATE_EXPLORING_PRIOR_FREE);  // no hypothesis
  explore_from_sketch::RegistrationHypotheses hyps;
  hyps.header.stamp = ros::Time::now();
  hyps.header.frame_id = "world";
  hyps.hypotheses.push_back(corridorPrior().truth);
  hyp_pub_.publish(hyps);
  hover(1.5);
  spinFor(0.3);
  EXPECT_EQ(last_status_.state, ExplorationStatus::STATE_EXPLORING_PRIOR_GUIDED);
  EXPECT_TRUE(last_status_.has_active_hypothesis);
  EXPECT_EQ(last_status_.active_hypothesis_id, 3);
  ASSERT_EQ(last_guidepoints_.ids.size(), corridorPrior().guidepoints);
  EXPECT_EQ(last_guidepoints_.header.frame_id, "sketch");
  ASSERT_EQ(last_guidepoints_.states.size(), last_guidepoints_.ids.size());
  int seen = 0;
  for (uint8_t st : last_guidepoints_.states)
    seen += st == explore_from_sketch::Guidepoints::EXPLORING ||
            st == explore_from_sketch::Guidepoints::EXPLORED;
  EXPECT_GT(seen, 0) << "the guidepoints near the robot are being explored";
  for (const char* ns : {"guidepoints", "viewpoints", "tour"})
    EXPECT_TRUE(marker_ns_.count(ns)) << "no marker '" << ns << "' on planner_markers";
  ASSERT_GT(target_count_, 0);
}

// The markers of a manager that planned with a hypothesis: one non-empty marker per part.
TEST(PlannerMarkers, EveryPartOfThePlanIsDrawn) {
  efs::planner::testing::Scene room;
  room.room = {Eigen::Vector3d(0.15, -2.85, 0.15), Eigen::Vector3d(15.75, 3.15, 3.15)};
  efs::planner::GuidepointPrior prior;
  for (int i = 0; i < 4; ++i) {
    prior.ids.push_back(i);
    prior.positions_sketch_m.emplace_back(2.0 + 4.0 * i, 0.0);
  }
  prior.prm_distance_m = efs::planner::CostMatrix(4);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) prior.prm_distance_m(i, j) = 4.0 * std::abs(i - j);
  efs::planner::ExplorationManager m(efs::planner::ExplorationManagerConfig{}, prior);
  const Eigen::Vector3d o(2.0, 0.1, 1.6);
  std::vector<Eigen::Vector3f> pts;
  for (const Eigen::Vector3d& p : room.scanSphere(o, 1.0)) pts.push_back(p.cast<float>());
  m.insertScan(o, pts);
  m.setHypotheses({efs::planner::Hypothesis{5, efs::Sim2(), 1.0}});
  efs::planner::RobotPose robot;
  robot.position_world_m = o;
  ASSERT_TRUE(m.update(0.0, robot).has_goal);
  std_msgs::Header h;
  h.frame_id = "world";
  const auto markers = efs::planner::plannerMarkers(m, robot, h, {});
  ASSERT_FALSE(markers.markers.empty());
  EXPECT_EQ(markers.markers.front().action, visualization_msgs::Marker::DELETEALL);
  std::set<std::string> drawn;
  for (const auto& mk : markers.markers) {
    if (mk.action != visualization_msgs::Marker::ADD) continue;
    EXPECT_EQ(mk.header.frame_id, "world");
    if (mk.type == visualization_msgs::Marker::ARROW || !mk.points.empty()) drawn.insert(mk.ns);
    if (!mk.colors.empty()) {
      EXPECT_EQ(mk.colors.size(), mk.points.size()) << mk.ns;
    }
  }
  for (const char* ns :
       {"viewpoints", "guidepoints", "guidepoint_sequence", "tour", "goal", "frontiers"})
    EXPECT_TRUE(drawn.count(ns)) << "no marker '" << ns << "'";
  efs::planner::PlannerMarkerOptions few;
  few.max_frontier_cells = 10;
  for (const auto& mk : efs::planner::plannerMarkers(m, robot, h, few).markers)
    if (mk.ns == "frontiers") {
      EXPECT_LE(mk.points.size(), 10u);
    }
}

// Bad configuration stops the node at start-up with one message naming the parameter.
// `_key:=value` arguments stay on the parameter server: each run clears the one it set.
TEST(PlannerNodeConfig, BadModeAndMissingBundleStopCleanly) {
  const std::string ns = "/prior_guided_planner_node_under_test/";
  const auto mode = efs::rostest::runNode("prior_guided_planner_node", "_mode:=epic", 20);
  EXPECT_EQ(mode.exit_code, 1) << mode.output;
  EXPECT_NE(mode.output.find("mode"), std::string::npos) << mode.output;
  EXPECT_NE(mode.output.find("nearest_frontier"), std::string::npos) << mode.output;
  ros::param::del(ns + "mode");
  const auto bundle = efs::rostest::runNode("prior_guided_planner_node",
                                            "_prior_bundle_path:=/nonexistent/x.prior", 20);
  EXPECT_EQ(bundle.exit_code, 1) << bundle.output;
  EXPECT_NE(bundle.output.find("prior_bundle_path"), std::string::npos) << bundle.output;
  ros::param::del(ns + "prior_bundle_path");
  const auto typo = efs::rostest::runNode("prior_guided_planner_node", "_rho:=3.0", 20);
  EXPECT_EQ(typo.exit_code, 1) << typo.output;
  EXPECT_NE(typo.output.find("rho"), std::string::npos) << typo.output;
  EXPECT_TRUE(efs::rostest::nodeAlive(kNode));  // the launched node is not disturbed
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "prior_guided_planner_rostest");
  return RUN_ALL_TESTS();
}
