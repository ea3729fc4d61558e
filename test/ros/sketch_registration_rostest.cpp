// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Live interface of sketch_registration_node. The test draws a synthetic office floor as a
// 0.1 m/px line drawing, builds and saves its prior bundle, starts the node on it and feeds it
// registration frames (robot position + accumulated local map) from the same floor placed in the
// world by a known similarity. The node must publish hypotheses with status OK and the best one
// near the truth, and markers of the sketch boundary in the world. Bad frames (empty map, NaN
// position, NaN points, a cloud without xyz) are reported in the status and the node keeps
// running; a missing, corrupt or unset bundle stops it with a message naming the file or key.
#include <explore_from_sketch/RegistrationFrame.h>
#include <explore_from_sketch/RegistrationHypotheses.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include <unistd.h>

#include <sys/wait.h>
#include <array>
#include <cmath>
#include <csignal>
#include <fstream>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "efs_common/sim2.h"
#include "efs_common_ros/cloud_conversions.h"
#include "prior_map_tools/prior_map_builder.h"
#include "ros_test_utils.h"
#include "sketch_registration/synthetic_scene.h"

namespace {

namespace syn = efs::registration::synthetic;
namespace pm = efs::prior_map;
using efs::Sim2;
using Eigen::Vector2d;
using explore_from_sketch::RegistrationHypotheses;

constexpr double kMetresPerPixel = 0.1;
const Vector2d kShift(2.0, 2.0);  // the plan's lower-left corner in the sketch frame
const Sim2 kTruth(0.6, 1.3, Vector2d(15.0, -8.0));

std::string tmpDir() {
  const char* d = std::getenv("ROS_LOG_DIR");
  return d ? d : "/tmp";
}

/// The office floor drawn as a sketch: walls as 2-px strokes, 0.1 m per pixel.
cv::Mat1b drawPlan(const syn::FloorPlan& plan, const Vector2d& hi) {
  const int w = static_cast<int>(std::ceil((hi.x() + 2 * kShift.x()) / kMetresPerPixel));
  const int h = static_cast<int>(std::ceil((hi.y() + 2 * kShift.y()) / kMetresPerPixel));
  cv::Mat1b img(h, w, uint8_t(255));
  const auto px = [&](const Vector2d& p) {
    return cv::Point(static_cast<int>(std::lround(p.x() / kMetresPerPixel - 0.5)),
                     static_cast<int>(std::lround(h - p.y() / kMetresPerPixel - 0.5)));
  };
  for (const syn::Segment& s : plan) cv::line(img, px(s.a), px(s.b), cv::Scalar(0), 2);
  return img;
}

struct Scene {
  syn::Scenario scenario;
  std::string bundle_path;
};

Scene& scene() {
  static Scene s = [] {
    Vector2d lo, hi;
    std::vector<syn::Box> solids;
    syn::FloorPlan plan = syn::makeOfficeFloor(&lo, &hi, &solids);
    const Vector2d shift = kShift - lo;
    for (syn::Segment& seg : plan) {
      seg.a += shift;
      seg.b += shift;
    }
    for (syn::Box& b : solids) {
      b.min_m += shift;
      b.max_m += shift;
    }
    efs::registration::Points2d waypoints = {{3, 18},  {25, 18}, {42, 18}, {42, 37}, {42, 25},
                                             {52, 25}, {52, 18}, {58, 18}, {58, 10}, {38, 10}};
    for (Vector2d& w : waypoints) w += shift;
    Scene out;
    out.scenario = syn::makeScenario(plan, solids, lo + shift, hi + shift, kTruth, waypoints);
    pm::SketchLoadConfig lc;
    lc.kind = pm::SketchKind::kLineDrawing;
    lc.scale_guess_m_per_px = kMetresPerPixel;
    pm::PriorMapConfig config;
    config.load = lc;
    config.guidepoints.mapping_range_m = 5.0;
    const pm::PriorBundle bundle =
        pm::buildPriorBundle(pm::sketchFromImage(drawPlan(plan, hi + shift), lc, "office"), config);
    out.bundle_path = tmpDir() + "/sketch_registration_rostest_office.prior";
    pm::savePriorBundle(bundle, out.bundle_path);
    return out;
  }();
  return s;
}

/// Starts a node executable (beside this test) in the background; stopped by the destructor.
class BackgroundNode {
 public:
  BackgroundNode(const std::string& node, const std::string& name,
                 const std::vector<std::string>& args) {
    std::array<char, 4096> self{};
    const ssize_t n = readlink("/proc/self/exe", self.data(), self.size() - 1);
    std::string dir(self.data(), n > 0 ? static_cast<size_t>(n) : 0);
    const std::string exe = dir.substr(0, dir.rfind('/')) + "/" + node;
    std::vector<std::string> argv_s = {exe, "__name:=" + name};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    pid_ = fork();
    if (pid_ == 0) {
      std::vector<char*> argv;
      for (auto& a : argv_s) argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(exe.c_str(), argv.data());
      _exit(127);
    }
  }
  ~BackgroundNode() {
    if (pid_ <= 0) return;
    kill(pid_, SIGINT);
    int status = 0;
    for (int i = 0; i < 100 && waitpid(pid_, &status, WNOHANG) == 0; ++i) usleep(50000);
    if (waitpid(pid_, &status, WNOHANG) == 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, &status, 0);
    }
  }
  /// True while the process runs.
  bool running() const {
    int status = 0;
    return pid_ > 0 && waitpid(pid_, &status, WNOHANG) == 0;
  }

 private:
  pid_t pid_ = -1;
};

class SketchRegistrationNodeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene();
    node_ = std::make_unique<BackgroundNode>(
        "sketch_registration_node", "sketch_registration_live",
        std::vector<std::string>{"_prior_bundle_path:=" + scene().bundle_path});
  }
  static void TearDownTestSuite() { node_.reset(); }

  void SetUp() override {
    frame_pub_ = nh_.advertise<explore_from_sketch::RegistrationFrame>("/registration_frame", 5);
    hyp_sub_ = nh_.subscribe("/hypotheses", 10, &SketchRegistrationNodeTest::onHypotheses, this);
    marker_sub_ =
        nh_.subscribe("/registration_markers", 10, &SketchRegistrationNodeTest::onMarkers, this);
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(60.0);
    while (frame_pub_.getNumSubscribers() == 0 && ros::WallTime::now() < end) {
      ros::WallDuration(0.05).sleep();
    }
    ASSERT_GT(frame_pub_.getNumSubscribers(), 0u) << "the node did not subscribe";
  }

  void onHypotheses(const RegistrationHypotheses::ConstPtr& m) { last_hyp_ = m; }
  void onMarkers(const visualization_msgs::MarkerArray::ConstPtr& m) { last_markers_ = m; }

  /// Publishes a frame and waits for the hypotheses answering it (same stamp).
  RegistrationHypotheses::ConstPtr send(double stamp_s, const Eigen::Vector3d& robot,
                                        const sensor_msgs::PointCloud2& cloud) {
    explore_from_sketch::RegistrationFrame f;
    f.header.stamp = ros::Time(stamp_s);
    f.header.frame_id = "world";
    f.robot_position.x = robot.x();
    f.robot_position.y = robot.y();
    f.robot_position.z = robot.z();
    f.local_map = cloud;
    frame_pub_.publish(f);
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(30.0);
    while (ros::WallTime::now() < end) {
      ros::spinOnce();
      if (last_hyp_ && last_hyp_->header.stamp == f.header.stamp) return last_hyp_;
      ros::WallDuration(0.01).sleep();
    }
    return nullptr;
  }

  static sensor_msgs::PointCloud2 cloudOf(const efs::registration::Points3d& pts) {
    std::vector<Eigen::Vector3f> v;
    for (const auto& p : pts) v.push_back(p.cast<float>());
    std_msgs::Header h;
    h.frame_id = "world";
    return efs::ros_common::toPointCloud2(v, h);
  }

  static Sim2 toSim2(const explore_from_sketch::RegistrationHypothesis& h) {
    Sim2 T(h.yaw, h.scale, Vector2d(h.tx, h.ty), h.reflected);
    T.stretch = std::exp(h.log_stretch);
    T.stretch_axis_rad = h.stretch_axis;
    return T;
  }

  /// Largest distance between where `T` and the truth put the sketch's wall samples.
  static double worstError(const Sim2& T) {
    double worst = 0.0;
    for (const syn::Segment& s : scene().scenario.sketch_plan) {
      for (const Vector2d& p : {s.a, s.b}) {
        worst = std::max(worst, (T.apply(p) - kTruth.apply(p)).norm());
      }
    }
    return worst;
  }

  ros::NodeHandle nh_;
  ros::Publisher frame_pub_;
  ros::Subscriber hyp_sub_, marker_sub_;
  RegistrationHypotheses::ConstPtr last_hyp_;
  visualization_msgs::MarkerArray::ConstPtr last_markers_;
  static std::unique_ptr<BackgroundNode> node_;
  static double next_stamp_s_;
};

std::unique_ptr<BackgroundNode> SketchRegistrationNodeTest::node_;
double SketchRegistrationNodeTest::next_stamp_s_ = 100.0;

TEST_F(SketchRegistrationNodeTest, RegistersTheOfficeNearTheTruth) {
  const syn::Scenario& sc = scene().scenario;
  syn::LocalMapSimulator sim(sc.world_plan, syn::LocalMapSimulator::Config{});
  RegistrationHypotheses::ConstPtr last;
  int ok_frames = 0;
  for (size_t i = 0; i < sc.path_world_m.size(); ++i) {
    sim.scanAt(sc.path_world_m[i]);
    if (i % 5 != 4) continue;
    const Vector2d p = sc.path_world_m[i];
    next_stamp_s_ += 5.0;
    last = send(next_stamp_s_, {p.x(), p.y(), 1.5}, cloudOf(sim.localMap(p, 40.0)));
    ASSERT_TRUE(last) << "no hypotheses for frame " << i;
    EXPECT_NE(last->status, RegistrationHypotheses::STATUS_BAD_INPUT) << last->status_text;
    EXPECT_FALSE(last->status_text.empty());
    if (last->status == RegistrationHypotheses::STATUS_OK && !last->hypotheses.empty() &&
        worstError(toSim2(last->hypotheses.front())) < 1.0) {
      if (++ok_frames >= 2) break;
    }
  }
  ASSERT_TRUE(last);
  ASSERT_EQ(last->status, RegistrationHypotheses::STATUS_OK) << last->status_text;
  ASSERT_FALSE(last->hypotheses.empty());
  EXPECT_EQ(last->header.frame_id, "world");
  const auto& best = last->hypotheses.front();
  EXPECT_LT(worstError(toSim2(best)), 1.0);
  EXPECT_NEAR(best.scale, kTruth.scale, 0.05);
  EXPECT_FALSE(best.reflected);
  double total = 0.0;
  for (const auto& h : last->hypotheses) {
    EXPECT_GE(h.confidence, 0.0);
    EXPECT_LE(h.confidence, 1.0);
    EXPECT_LE(h.fitness, 0.6);
    total += h.confidence;
  }
  EXPECT_NEAR(total, 1.0, 1e-6);
  EXPECT_GE(best.confidence, last->hypotheses.back().confidence);

  // Markers: the boundary of the best hypothesis lies on the world's walls.
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(5.0);
  while ((!last_markers_ || last_markers_->markers.empty() ||
          last_markers_->markers.back().header.stamp != last->header.stamp) &&
         ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.02).sleep();
  }
  ASSERT_TRUE(last_markers_);
  EXPECT_EQ(last_markers_->markers.front().action, visualization_msgs::Marker::DELETEALL);
  bool found_boundary = false, found_candidates = false;
  for (const auto& m : last_markers_->markers) {
    if (m.ns == "sketch_boundary" && m.id == static_cast<int>(best.id)) {
      found_boundary = true;
      EXPECT_EQ(m.header.frame_id, "world");
      ASSERT_GT(m.points.size(), 100u);
      int near = 0;
      for (const auto& q : m.points) {
        if (syn::distanceToPlan(sc.world_plan, Vector2d(q.x, q.y)) < 1.0) ++near;
      }
      // Drawn at the robot's height (1.5 m in the frames sent), not at z = 0.
      EXPECT_NEAR(m.points.front().z, 1.5, 1e-9);
      EXPECT_GT(near, 0.9 * m.points.size());
      EXPECT_GT(m.color.g, m.color.r * best.confidence);
    }
    if (m.ns == "candidates") {
      found_candidates = true;
      EXPECT_EQ(m.header.frame_id, "world");
      EXPECT_FALSE(m.points.empty());
    }
  }
  EXPECT_TRUE(found_boundary);
  EXPECT_TRUE(found_candidates);
}

TEST_F(SketchRegistrationNodeTest, BadFramesAreReportedAndTheNodeKeepsRunning) {
  const Eigen::Vector3d robot(kTruth.apply(Vector2d(20, 20)).x(),
                              kTruth.apply(Vector2d(20, 20)).y(), 1.5);
  // Empty local map.
  next_stamp_s_ += 5.0;
  auto r = send(next_stamp_s_, robot, cloudOf({}));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, RegistrationHypotheses::STATUS_BAD_INPUT);
  EXPECT_NE(r->status_text.find("local map"), std::string::npos) << r->status_text;
  // Only NaN points.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  next_stamp_s_ += 5.0;
  r = send(next_stamp_s_, robot, cloudOf(efs::registration::Points3d(500, {nan, nan, nan})));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, RegistrationHypotheses::STATUS_BAD_INPUT);
  EXPECT_NE(r->status_text.find("non-finite"), std::string::npos) << r->status_text;
  // NaN robot position with a good map.
  syn::LocalMapSimulator sim(scene().scenario.world_plan, syn::LocalMapSimulator::Config{});
  sim.scanAt(robot.head<2>());
  next_stamp_s_ += 5.0;
  r = send(next_stamp_s_, {nan, robot.y(), 1.5}, cloudOf(sim.localMap(robot.head<2>(), 40.0)));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, RegistrationHypotheses::STATUS_BAD_INPUT) << r->status_text;
  // A cloud without x/y/z fields.
  sensor_msgs::PointCloud2 no_xyz;
  no_xyz.header.frame_id = "world";
  no_xyz.width = 3;
  no_xyz.height = 1;
  no_xyz.point_step = 4;
  no_xyz.row_step = 12;
  no_xyz.data.assign(12, 0);
  next_stamp_s_ += 5.0;
  r = send(next_stamp_s_, robot, no_xyz);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, RegistrationHypotheses::STATUS_BAD_INPUT);
  EXPECT_NE(r->status_text.find("unreadable"), std::string::npos) << r->status_text;
  // A frame in another frame_id is refused, naming it.
  explore_from_sketch::RegistrationFrame f;
  next_stamp_s_ += 5.0;
  f.header.stamp = ros::Time(next_stamp_s_);
  f.header.frame_id = "camera_init";
  frame_pub_.publish(f);
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
  while ((!last_hyp_ || last_hyp_->header.stamp != f.header.stamp) && ros::WallTime::now() < end) {
    ros::spinOnce();
    ros::WallDuration(0.01).sleep();
  }
  ASSERT_TRUE(last_hyp_);
  EXPECT_EQ(last_hyp_->status, RegistrationHypotheses::STATUS_BAD_INPUT);
  EXPECT_NE(last_hyp_->status_text.find("camera_init"), std::string::npos);
  EXPECT_TRUE(node_->running());
  EXPECT_TRUE(efs::rostest::nodeAlive("/sketch_registration_live"));
}

void expectCleanFailure(const std::string& args, const std::string& needle) {
  const auto result = efs::rostest::runNode("sketch_registration_node", args, 60);
  EXPECT_NE(result.exit_code, 0) << result.output;
  EXPECT_LT(result.exit_code, 128) << "crashed: " << result.output;
  EXPECT_NE(result.output.find(needle), std::string::npos) << result.output;
}

TEST(SketchRegistrationBadBundle, MissingFileIsNamed) {
  expectCleanFailure("_prior_bundle_path:=/nonexistent/office.prior", "/nonexistent/office.prior");
}

TEST(SketchRegistrationBadBundle, CorruptFileIsNamed) {
  const std::string path = tmpDir() + "/sketch_registration_rostest_corrupt.prior";
  std::ofstream(path) << "EFSPRIOR this is not a bundle";
  expectCleanFailure("_prior_bundle_path:=" + path, path);
}

TEST(SketchRegistrationBadBundle, UnsetPathIsNamed) {
  // Private parameters set by earlier runs persist on the master.
  ros::param::del("/sketch_registration_node_under_test");
  expectCleanFailure("", "prior_bundle_path");
}

TEST(SketchRegistrationBadBundle, AbsurdParameterIsNamed) {
  expectCleanFailure("_prior_bundle_path:=" + scene().bundle_path + " _eta:=-0.5", "eta");
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "sketch_registration_rostest");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
