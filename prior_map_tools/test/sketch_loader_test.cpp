// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/sketch_loader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "efs_common/testing/paths.h"
#include "prior_map_tools/prior_map_error.h"
#include "test_sketches.h"

namespace efs::prior_map {
namespace {

std::string tmpPath(const std::string& name) {
  return efs::testing::testOutputDir() + "/pmt_" + name;
}

void expectError(const std::string& path, const SketchLoadConfig& config,
                 const std::string& needle) {
  try {
    loadSketch(path, config);
    FAIL() << "expected PriorMapError containing '" << needle << "'";
  } catch (const PriorMapError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(needle), std::string::npos) << what;
  }
}

TEST(SketchLoader, MissingFile) { expectError(tmpPath("does_not_exist.png"), {}, "no such file"); }

TEST(SketchLoader, NotAnImage) {
  const std::string p = tmpPath("not_an_image.png");
  std::ofstream(p) << "this is text, not a PNG";
  expectError(p, {}, "not an image");
}

TEST(SketchLoader, EmptyFile) {
  const std::string p = tmpPath("empty.png");
  std::ofstream(p, std::ios::trunc).close();
  expectError(p, {}, "empty file");
}

TEST(SketchLoader, ZeroSizePngHeader) {
  // A PNG signature and an IHDR that claims 0 x 0 pixels.
  const std::string p = tmpPath("zero.png");
  const unsigned char bytes[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0,
                                 13,   'I', 'H', 'D', 'R',  0,    0,    0,    0, 0, 0,
                                 0,    0,   8,   0,   0,    0,    0,    0,    0, 0, 0};
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(bytes), sizeof(bytes));
  expectError(p, {}, "zero-size image");
}

TEST(SketchLoader, ImageBeyondSizeLimitIsRefusedBeforeDecoding) {
  const std::string p = tmpPath("big.png");
  cv::imwrite(p, cv::Mat1b(100, 100, uint8_t(255)));
  SketchLoadConfig config;
  config.max_image_pixels = 5000;
  expectError(p, config, "exceeds the limit");
}

TEST(SketchLoader, BadScaleGuessIsNamed) {
  const std::string p = tmpPath("building.png");
  cv::imwrite(p, test::drawBuilding());
  for (double bad : {0.0, -0.1, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()}) {
    SketchLoadConfig config;
    config.scale_guess_m_per_px = bad;
    expectError(p, config, "scale_guess_m_per_px");
  }
}

TEST(SketchLoader, GreyDrawingGivesWallsAndFrame) {
  const std::string p = tmpPath("building.png");
  cv::imwrite(p, test::drawBuilding());
  SketchLoadConfig config;
  config.scale_guess_m_per_px = 0.2;
  const LoadedSketch s = loadSketch(p, config);
  EXPECT_EQ(s.kind, SketchKind::kLineDrawing);
  EXPECT_EQ(s.frame.width_px, 400);
  EXPECT_EQ(s.frame.height_px, 300);
  EXPECT_DOUBLE_EQ(s.frame.m_per_px, 0.2);
  EXPECT_EQ(s.wall_mask(50, 200), 255);  // north outer wall
  EXPECT_EQ(s.wall_mask(150, 200), 0);   // corridor
  EXPECT_EQ(cv::countNonZero(s.unknown_mask), 0);
  // Frame convention: pixel row 0 is the top; y is up.
  EXPECT_NEAR(s.frame.pixelCenter(0, 299).y(), 0.1, 1e-12);
  EXPECT_NEAR(s.frame.toPixel(s.frame.pixelCenter(12, 34)).x(), 12.5, 1e-9);
}

TEST(SketchLoader, ColourAndTransparentImagesGiveTheSameWalls) {
  const cv::Mat1b grey = test::drawBuilding();
  cv::Mat bgr;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  // Transparent background (whatever colour it stores) with opaque black lines.
  cv::Mat bgra(grey.size(), CV_8UC4, cv::Scalar(0, 0, 0, 0));
  bgra.setTo(cv::Scalar(0, 0, 0, 255), grey < 128);
  const std::string pc = tmpPath("colour.png"), pa = tmpPath("alpha.png");
  cv::imwrite(pc, bgr);
  cv::imwrite(pa, bgra);
  const LoadedSketch a = loadSketch(pc, {});
  const LoadedSketch b = loadSketch(pa, {});
  EXPECT_EQ(cv::countNonZero(a.wall_mask != b.wall_mask), 0);
  EXPECT_EQ(cv::countNonZero(a.wall_mask), cv::countNonZero(grey < 128));
}

TEST(SketchLoader, MapServerYamlTakesResolutionOriginAndUnknown) {
  cv::Mat1b grid(40, 60, uint8_t(205));                             // unknown
  grid(cv::Rect(10, 10, 40, 20)).setTo(254);                        // free
  cv::rectangle(grid, cv::Rect(10, 10, 40, 20), cv::Scalar(0), 1);  // occupied border
  const std::string pgm = tmpPath("grid.pgm"), yaml = tmpPath("grid.yaml");
  cv::imwrite(pgm, grid);
  std::ofstream(yaml) << "image: pmt_grid.pgm\nresolution: 0.05  # m/px\n"
                         "origin: [-1.5, 2.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
                         "free_thresh: 0.196\n";
  const LoadedSketch s = loadSketch(yaml, {});
  EXPECT_EQ(s.kind, SketchKind::kOccupancyGrid);
  EXPECT_DOUBLE_EQ(s.frame.m_per_px, 0.05);
  EXPECT_DOUBLE_EQ(s.frame.origin_m.x(), -1.5);
  EXPECT_DOUBLE_EQ(s.frame.origin_m.y(), 2.0);
  EXPECT_EQ(s.unknown_mask(0, 0), 255);
  EXPECT_EQ(s.wall_mask(10, 20), 255);
  EXPECT_EQ(s.wall_mask(20, 20) | s.unknown_mask(20, 20), 0);
}

TEST(SketchLoader, MalformedYamlNamesTheKey) {
  const std::string yaml = tmpPath("bad.yaml");
  std::ofstream(yaml) << "image: pmt_grid.pgm\norigin: [0, 0, 0]\n";
  expectError(yaml, {}, "resolution");
  std::ofstream(yaml, std::ios::trunc) << "image: pmt_grid.pgm\nresolution: fast\n";
  expectError(yaml, {}, "not a number");
}

TEST(SketchLoader, AutoKindRecognisesOccupancyGridImages) {
  cv::Mat1b grid(40, 60, uint8_t(205));
  grid(cv::Rect(10, 10, 40, 20)).setTo(254);
  const LoadedSketch s = sketchFromImage(grid, {});
  EXPECT_EQ(s.kind, SketchKind::kOccupancyGrid);
  EXPECT_THROW(sketchFromImage(cv::Mat(), {}), PriorMapError);
}

TEST(SketchLoader, RealEd21SketchesLoadAsDrawings) {
  for (const char* name :
       {"sketch_ed21.png", "sketch_ed21_1.png", "sketch_ed21_2.png", "sketch_ed21_3.png"}) {
    const LoadedSketch s =
        loadSketch(efs::testing::sharedDataPath(std::string("ed21/") + name), {});
    EXPECT_EQ(s.kind, SketchKind::kLineDrawing) << name;
    EXPECT_GT(cv::countNonZero(s.wall_mask), 1000) << name;
  }
}

}  // namespace
}  // namespace efs::prior_map
