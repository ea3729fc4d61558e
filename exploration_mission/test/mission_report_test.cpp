// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <opencv2/imgproc.hpp>

#include "efs_common/testing/paths.h"
#include "exploration_mission/mission_prior.h"
#include "exploration_mission/mission_report.h"

namespace efs::mission {
namespace {

TEST(RegistrationError, IsTheRmsDisplacementOfTheSketchPoints) {
  const std::vector<Eigen::Vector2d> points{{0, 0}, {10, 0}, {0, 10}, {10, 10}};
  const Sim2 truth(0.3, 2.0, Eigen::Vector2d(5, -3));
  EXPECT_NEAR(registrationErrorRmse(truth, truth, points), 0.0, 1e-12);
  Sim2 shifted = truth;
  shifted.t_m += Eigen::Vector2d(0.3, 0.4);  // every point moves by 0.5
  EXPECT_NEAR(registrationErrorRmse(shifted, truth, points), 0.5, 1e-12);
  Sim2 scaled = truth;
  scaled.scale = 2.2;  // points move by 0.2 x their distance from the origin: 0, 2, 2, 2.83
  const double expected = std::sqrt((0.0 + 4.0 + 4.0 + 8.0) / 4.0);
  EXPECT_NEAR(registrationErrorRmse(scaled, truth, points), expected, 1e-9);
  EXPECT_EQ(registrationErrorRmse(scaled, truth, {}), 0.0);
}

/// A drawing: a closed room with an inner wall, black on white.
cv::Mat drawRoom() {
  cv::Mat img(200, 300, CV_8UC1, cv::Scalar(255));
  cv::rectangle(img, cv::Rect(20, 20, 260, 160), cv::Scalar(0), 2);
  cv::line(img, cv::Point(150, 20), cv::Point(150, 120), cv::Scalar(0), 2);
  return img;
}

// Where coverage fell short is in both reports.
TEST(MissionReport, UnseenSurfaceIsReported) {
  MissionReport r;
  r.unseen_up = 100864;
  r.unseen_down = 72336;
  r.unseen_sideways = 68384;
  r.truth_up = 320000;
  r.truth_down = 310000;
  r.truth_sideways = 141536;
  const std::string md = toMarkdown(r);
  EXPECT_NE(
      md.find("| surface never seen: facing up / down / sideways | 100864 of 320000 / 72336 of "
              "310000 / 68384 of 141536 voxels (coverage_gaps.png) |"),
      std::string::npos)
      << md;
  const std::string json = toJson(r);
  EXPECT_NE(json.find("\"unseen_surface\": {\"up\": 100864, \"down\": 72336, \"sideways\": 68384, "
                      "\"up_of\": 320000, \"down_of\": 310000, \"sideways_of\": 141536}"),
            std::string::npos)
      << json;
}

// The benchmark's picture of a world's flights: each panel scaled to the row height under its
// caption, in the given order, left-aligned on white.
TEST(MissionReport, PanelsAreStackedUnderTheirCaptions) {
  const cv::Mat red(100, 200, CV_8UC3, cv::Scalar(0, 0, 255));
  const cv::Mat green(400, 200, CV_8UC3, cv::Scalar(0, 255, 0));
  const cv::Mat out = stackLabelledPanels({{"a", red}, {"b", green}}, 200);
  ASSERT_EQ(out.type(), CV_8UC3);
  EXPECT_EQ(out.cols, 400);  // red at 400 x 200; green at 100 x 200
  const int banner = out.rows / 2 - 200;
  EXPECT_GT(banner, 10);
  const cv::Vec3b kRed(0, 0, 255), kGreen(0, 255, 0), kWhite(255, 255, 255);
  EXPECT_EQ(out.at<cv::Vec3b>(banner + 100, 300), kRed);
  EXPECT_EQ(out.at<cv::Vec3b>(2 * banner + 300, 50), kGreen);
  EXPECT_EQ(out.at<cv::Vec3b>(2 * banner + 300, 300), kWhite);
  EXPECT_THROW(stackLabelledPanels({{"empty", cv::Mat()}}, 200), std::invalid_argument);
  EXPECT_THROW(stackLabelledPanels({{"grey", cv::Mat(10, 10, CV_8UC1)}}, 200),
               std::invalid_argument);
  EXPECT_THROW(stackLabelledPanels({{"a", red}}, 0), std::invalid_argument);
  EXPECT_TRUE(stackLabelledPanels({}, 200).empty());
}

TEST(MissionPrior, TruthIsReExpressedInTheBundleFrame) {
  // The drawing says 0.1 m/px; the user guesses 0.2 m/px. A pixel centre must land on the same
  // world point through either frame.
  const Sim2 truth_drawing(0.7, 1.5, Eigen::Vector2d(12, -4));
  prior_map::PriorMapConfig config;
  config.guidepoints.mapping_range_m = 3.0;
  const MissionPrior prior =
      prepareMissionPrior(drawRoom(), 0.2, config, truth_drawing, 0.1, "room");
  ASSERT_TRUE(prior.T_world_sketch_truth.has_value());
  EXPECT_DOUBLE_EQ(prior.scale_guess_m_per_px, 0.2);
  EXPECT_FALSE(prior.bundle.guidepoints.empty());
  const double u = 37, v = 91;  // a pixel
  const Eigen::Vector2d p_drawing(0.1 * (u + 0.5), 0.1 * (200 - v - 0.5));
  const Eigen::Vector2d p_bundle = prior.bundle.frame.pixelCenter(u, v);
  EXPECT_LT((prior.T_world_sketch_truth->apply(p_bundle) - truth_drawing.apply(p_drawing)).norm(),
            1e-9);
}

TEST(MissionPrior, UnusableSketchIsRefusedWithAMessage) {
  prior_map::PriorMapConfig config;
  const cv::Mat blank(100, 100, CV_8UC1, cv::Scalar(255));
  EXPECT_ANY_THROW(prepareMissionPrior(blank, 0.1, config, std::nullopt, 1.0, "blank"));
  EXPECT_ANY_THROW(prepareMissionPrior(drawRoom(), std::nan(""), config, std::nullopt, 1.0, "nan"));
}

TEST(MissionPrior, TruthFileRoundTripsAndBadFilesAreNamed) {
  const std::string dir = efs::testing::testOutputDir();
  const Sim2 truth(0.3, 1.7, Eigen::Vector2d(-2.5, 8.25), true);
  saveTruth(truth, dir + "/truth.yaml");
  const Sim2 back = loadTruth(dir + "/truth.yaml");
  EXPECT_NEAR(back.yaw_rad, truth.yaw_rad, 1e-12);
  EXPECT_NEAR(back.scale, truth.scale, 1e-12);
  EXPECT_NEAR((back.t_m - truth.t_m).norm(), 0.0, 1e-12);
  EXPECT_TRUE(back.reflected);

  auto refused = [&](const std::string& text) -> std::string {
    std::ofstream(dir + "/bad_truth.yaml") << text;
    try {
      loadTruth(dir + "/bad_truth.yaml");
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "accepted";
  };
  const std::string head = "T_world_sketch:\n  yaw_rad: 0.1\n  tx_m: 1\n  ty_m: 2\n";
  EXPECT_NE(refused(head + "  reflected: false\n").find("T_world_sketch/scale"), std::string::npos);
  EXPECT_NE(refused(head + "  scale: nan\n  reflected: false\n").find("not a finite number"),
            std::string::npos);
  EXPECT_NE(refused(head + "  scale: 1x\n  reflected: false\n").find("not a finite number"),
            std::string::npos);
  EXPECT_NE(refused(head + "  scale: -1\n  reflected: false\n").find("must be > 0"),
            std::string::npos);
  EXPECT_NE(refused(head + "  scale: 1\n  reflected: maybe\n").find("reflected"),
            std::string::npos);
  EXPECT_EQ(refused(head + "  scale: 1\n  reflected: false\n"), "accepted");
  EXPECT_ANY_THROW(loadTruth(dir + "/no_such_truth.yaml"));
}

}  // namespace
}  // namespace efs::mission
