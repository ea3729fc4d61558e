// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Registration inputs from a prior bundle built from a generated drawing: a 30 x 20 m building
// (0.1 m per pixel guess) with a corridor, rooms and doors, drawn as 2-px black strokes.
#include "sketch_registration/prior_inputs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "efs_common/config_check.h"
#include "prior_map_tools/prior_map_builder.h"

namespace efs::registration {
namespace {

namespace pm = efs::prior_map;

cv::Mat1b drawFloor() {
  cv::Mat1b img(260, 360, uint8_t(255));
  const cv::Scalar ink(0);
  cv::rectangle(img, cv::Point(30, 30), cv::Point(330, 230), ink, 2);
  // Corridor between rows 110 and 150; doors of 14 px into two north and two south rooms.
  for (int y : {110, 150}) {
    cv::line(img, {30, y}, {93, y}, ink, 2);
    cv::line(img, {107, y}, {243, y}, ink, 2);
    cv::line(img, {257, y}, {330, y}, ink, 2);
  }
  cv::line(img, {180, 30}, {180, 110}, ink, 2);
  cv::line(img, {150, 150}, {150, 230}, ink, 2);
  return img;
}

pm::PriorBundle floorBundle() {
  pm::SketchLoadConfig lc;
  lc.kind = pm::SketchKind::kLineDrawing;
  lc.scale_guess_m_per_px = 0.1;
  pm::PriorMapConfig config;
  config.load = lc;
  config.guidepoints.mapping_range_m = 3.0;
  return pm::buildPriorBundle(pm::sketchFromImage(drawFloor(), lc, "floor.png"), config);
}

bool traversableAt(const pm::PriorBundle& b, const Eigen::Vector2d& p) {
  const Eigen::Vector2d px = b.frame.toPixel(p);
  const int col = static_cast<int>(std::floor(px.x())), row = static_cast<int>(std::floor(px.y()));
  if (col < 0 || row < 0 || col >= b.traversable.cols || row >= b.traversable.rows) return false;
  return b.traversable(row, col) != 0;
}

double nearest(const Points2d& set, const Eigen::Vector2d& p) {
  double best = INFINITY;
  for (const auto& q : set) best = std::min(best, (q - p).norm());
  return best;
}

TEST(PriorInputs, CandidatesLieOnTheGapGridInsideTheTraversableRegion) {
  const pm::PriorBundle b = floorBundle();
  const double d_gap_m = 1.0;
  const RegistrationPrior prior = registrationPriorFromBundle(b, d_gap_m);
  ASSERT_FALSE(prior.candidates_sketch_m.empty());
  for (const auto& c : prior.candidates_sketch_m) {
    EXPECT_TRUE(traversableAt(b, c)) << c.transpose();
    // On the lattice anchored half a gap inside the lower-left corner.
    const Eigen::Vector2d q = (c - b.frame.origin_m) / d_gap_m - Eigen::Vector2d::Constant(0.5);
    EXPECT_NEAR(q.x(), std::round(q.x()), 1e-6);
    EXPECT_NEAR(q.y(), std::round(q.y()), 1e-6);
  }
  // Every candidate has a neighbour exactly d_gap away (the region is wider than one gap).
  for (const auto& c : prior.candidates_sketch_m) {
    double best = INFINITY;
    for (const auto& o : prior.candidates_sketch_m) {
      if (&o != &c) best = std::min(best, (o - c).norm());
    }
    EXPECT_NEAR(best, d_gap_m, 1e-6) << c.transpose();
  }
  // One candidate per d_gap^2 of traversable area (the building's interior is ~29.6 x 19.6 m).
  const double area_m2 = cv::countNonZero(b.traversable) * b.frame.m_per_px * b.frame.m_per_px;
  // (The clearance mask is a little smaller than the lattice cells the interior holds.)
  EXPECT_NEAR(static_cast<double>(prior.candidates_sketch_m.size()), area_m2 / (d_gap_m * d_gap_m),
              0.15 * area_m2);
  // Nothing outside the building: the page's margin is never a candidate.
  for (const auto& c : prior.candidates_sketch_m) {
    EXPECT_GT(c.x(), 3.0);
    EXPECT_LT(c.x(), 33.0);
  }
  // A coarser gap gives about a quarter of the candidates (fewer where lattice rows fall on
  // walls).
  const size_t coarse = registrationPriorFromBundle(b, 2.0).candidates_sketch_m.size();
  EXPECT_GT(static_cast<double>(coarse), 0.5 * prior.candidates_sketch_m.size() / 4.0);
  EXPECT_LT(static_cast<double>(coarse), 1.1 * prior.candidates_sketch_m.size() / 4.0);
}

TEST(PriorInputs, BoundaryIsThinnedAndLiesOnTheWalls) {
  const pm::PriorBundle b = floorBundle();
  const Points2d walls = b.wallPoints();
  const double spacing_m = 0.2;
  const RegistrationPrior prior = registrationPriorFromBundle(b, 1.0, spacing_m);
  ASSERT_FALSE(prior.boundary_sketch_m.empty());
  EXPECT_LT(prior.boundary_sketch_m.size(), walls.size() / 3);
  for (const auto& p : prior.boundary_sketch_m) {
    EXPECT_LT(nearest(walls, p), 1e-9) << "boundary point off the ink " << p.transpose();
    EXPECT_FALSE(traversableAt(b, p));
  }
  // Every wall pixel is represented within the spacing; kept points are not closer than it.
  for (size_t i = 0; i < walls.size(); i += 7) {
    EXPECT_LT(nearest(prior.boundary_sketch_m, walls[i]), spacing_m + 1e-9);
  }
  for (size_t i = 0; i < prior.boundary_sketch_m.size(); i += 5) {
    const Eigen::Vector2d& p = prior.boundary_sketch_m[i];
    for (const auto& q : prior.boundary_sketch_m) {
      if (&q != &p) {
        EXPECT_GE((q - p).norm(), spacing_m - 1e-9);
      }
    }
  }
  // The strokes are 30 m + 20 m + ... long: one or two points across a stroke per spacing of
  // its length, not every pixel of its width.
  const double ink_length_m = 2 * (30.0 + 20.0) + 2 * (30.0 - 2 * 1.4) + 8.0 + 8.0;
  EXPECT_GT(static_cast<double>(prior.boundary_sketch_m.size()), 0.6 * ink_length_m / spacing_m);
  EXPECT_LT(static_cast<double>(prior.boundary_sketch_m.size()), 2.0 * ink_length_m / spacing_m);
}

TEST(PriorInputs, EmptyBundleGivesNoPointsAndBadSpacingIsRefused) {
  const pm::PriorBundle empty;
  const RegistrationPrior prior = registrationPriorFromBundle(empty, 1.0);
  EXPECT_TRUE(prior.boundary_sketch_m.empty());
  EXPECT_TRUE(prior.candidates_sketch_m.empty());
  const pm::PriorBundle b = floorBundle();
  for (double bad : {0.0, -1.0, std::nan("")}) {
    try {
      registrationPriorFromBundle(b, bad);
      FAIL() << "d_gap_m = " << bad << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("d_gap_m"), std::string::npos) << e.what();
    }
    try {
      registrationPriorFromBundle(b, 1.0, bad);
      FAIL() << "boundary_spacing_m = " << bad << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("boundary_spacing_m"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace efs::registration
