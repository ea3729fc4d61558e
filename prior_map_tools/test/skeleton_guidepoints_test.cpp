// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "efs_common/config_check.h"
#include "efs_common/testing/paths.h"
#include "prior_map_tools/guidepoints.h"
#include "prior_map_tools/skeleton_graph.h"
#include "prior_map_tools/traversable_region.h"
#include "test_sketches.h"

namespace efs::prior_map {
namespace {

struct Pipeline {
  LoadedSketch sketch;
  TraversableRegion region;
  SkeletonGraph skeleton;
};

Pipeline run(const cv::Mat1b& img, double m_per_px, const SkeletonConfig& sc = {}) {
  SketchLoadConfig lc;
  lc.scale_guess_m_per_px = m_per_px;
  Pipeline p;
  p.sketch = sketchFromImage(img, lc, "test");
  p.region = extractTraversable(p.sketch, {});
  p.skeleton = extractSkeleton(p.region.mask, m_per_px, sc);
  return p;
}

TEST(Skeleton, PlusCorridorHasOneJunctionAndFourArms) {
  const Pipeline p = run(test::drawPlus(), 0.1);
  int junctions = 0, ends = 0;
  for (const auto& n : p.skeleton.nodes) {
    junctions += n.degree >= 3;
    ends += n.degree == 1;
  }
  EXPECT_EQ(junctions, 1);
  EXPECT_EQ(ends, 4);
  EXPECT_EQ(p.skeleton.branches.size(), 4u);
  // Each arm is about 110 px from the centre to the end of the free corridor.
  for (const auto& b : p.skeleton.branches) EXPECT_NEAR(b.length_px, 110.0, 15.0);
  // The skeleton stays inside the region.
  EXPECT_EQ(cv::countNonZero(p.skeleton.mask & ~p.region.mask), 0);
}

TEST(Skeleton, ShortSpursArePruned) {
  // A corridor with a small bump: the bump's spur is shorter than the prune length.
  cv::Mat1b img(120, 300, uint8_t(255));
  cv::Mat1b inside = cv::Mat1b::zeros(img.size());
  cv::rectangle(inside, cv::Rect(20, 50, 260, 20), cv::Scalar(255), cv::FILLED);
  cv::rectangle(inside, cv::Rect(140, 40, 14, 10), cv::Scalar(255), cv::FILLED);
  cv::Mat1b edge;
  cv::dilate(inside, edge, cv::getStructuringElement(cv::MORPH_RECT, {5, 5}));
  img.setTo(0, edge & ~inside);
  SkeletonConfig keep;
  keep.spur_prune_length_m = 0.0;
  SkeletonConfig prune;
  prune.spur_prune_length_m = 2.5;  // 25 px at 0.1 m/px
  const Pipeline raw = run(img, 0.1, keep);
  const Pipeline pruned = run(img, 0.1, prune);
  EXPECT_GT(raw.skeleton.branches.size(), pruned.skeleton.branches.size());
  ASSERT_EQ(pruned.skeleton.branches.size(), 1u);
  EXPECT_GT(pruned.skeleton.branches[0].length_px, 200.0);
}

// A walled hall of 60 x 40 m at 0.1 m/px, with square pillars of `pillar_px` every 75 px
// (7.5 m) in rows 100 px apart, one of them on the hall's medial axis (y = 210).
cv::Mat1b drawHallWithPillars(int pillar_px) {
  cv::Mat1b img(420, 620, uint8_t(255));
  cv::rectangle(img, cv::Rect(10, 10, 600, 400), cv::Scalar(0), 2);
  if (pillar_px > 0)
    for (int y = 110; y <= 310; y += 100)
      for (int x = 85; x <= 535; x += 75)
        cv::rectangle(img, cv::Rect(x - pillar_px / 2, y - pillar_px / 2, pillar_px, pillar_px),
                      cv::Scalar(0), cv::FILLED);
  return img;
}

// Pixel of the sketch frame position `p_m`.
cv::Point pixelOf(const SketchFrame& frame, const Eigen::Vector2d& p_m) {
  const Eigen::Vector2d px = frame.toPixel(p_m);
  return {static_cast<int>(std::floor(px.x())), static_cast<int>(std::floor(px.y()))};
}

TEST(Skeleton, IslandsAreFilledOnlyWhenSmallAndEnclosed) {
  cv::Mat1b region(100, 200, uint8_t(255));
  region(cv::Rect(20, 20, 10, 10)).setTo(0);  // 10 px island: filled at 10 px
  region(cv::Rect(60, 20, 11, 10)).setTo(0);  // 11 px wide: kept
  region(cv::Rect(100, 0, 5, 5)).setTo(0);    // small, but touches the border: kept
  region(cv::Rect(150, 50, 3, 30)).setTo(0);  // a thin wall 30 px long: kept
  const cv::Mat1b filled = fillSmallIslands(region, 10.0);
  EXPECT_EQ(cv::countNonZero(filled(cv::Rect(20, 20, 10, 10))), 100);
  EXPECT_EQ(cv::countNonZero(filled(cv::Rect(60, 20, 11, 10))), 0);
  EXPECT_EQ(cv::countNonZero(filled(cv::Rect(100, 0, 5, 5))), 0);
  EXPECT_EQ(cv::countNonZero(filled(cv::Rect(150, 50, 3, 30))), 0);
  EXPECT_EQ(cv::countNonZero(filled), cv::countNonZero(region) + 100);
  // Off: the region unchanged.
  EXPECT_EQ(cv::countNonZero(fillSmallIslands(region, 0.0) != region), 0);
  SkeletonConfig absurd;
  absurd.max_island_extent_m = -1.0;
  EXPECT_THROW(absurd.validate(), ConfigError);
}

TEST(Skeleton, PillarsOfAHallMakeNoTopology) {
  const Pipeline bare = run(drawHallWithPillars(0), 0.1);
  const Pipeline pillars = run(drawHallWithPillars(6), 0.1);  // 0.6 m pillars
  SkeletonConfig off;
  off.max_island_extent_m = 0.0;
  const Pipeline meshed = run(drawHallWithPillars(6), 0.1, off);
  // Filled, the pillars leave the hall's skeleton as it is without them; unfilled, every pillar
  // is ringed by branches.
  EXPECT_EQ(pillars.skeleton.branches.size(), bare.skeleton.branches.size());
  EXPECT_GT(meshed.skeleton.branches.size(), 4 * bare.skeleton.branches.size());
  GuidepointConfig gc;
  gc.mapping_range_m = 5.0;
  const auto few = sampleGuidepoints(pillars.skeleton, pillars.region, pillars.sketch.frame, gc);
  const auto many = sampleGuidepoints(meshed.skeleton, meshed.region, meshed.sketch.frame, gc);
  EXPECT_LT(2 * few.size(), many.size());
  ASSERT_FALSE(few.empty());
  // The skeleton runs over the filled pillar on the medial axis; its guidepoints do not.
  for (const auto& g : few) {
    const cv::Point px = pixelOf(pillars.sketch.frame, g.position_m);
    EXPECT_GT(pillars.region.components(px.y, px.x), 0) << "a guidepoint on a pillar at " << px;
  }
}

TEST(Skeleton, ALargeIslandKeepsItsLoop) {
  cv::Mat1b img = drawHallWithPillars(0);
  cv::rectangle(img, cv::Rect(260, 170, 100, 80), cv::Scalar(0), cv::FILLED);  // 10 x 8 m block
  const Pipeline p = run(img, 0.1);
  // The skeleton passes the block on both sides (above and below its middle column).
  int above = 0, below = 0;
  for (int y = 0; y < p.skeleton.mask.rows; ++y) {
    above += p.skeleton.mask(y, 310) && y < 170;
    below += p.skeleton.mask(y, 310) && y >= 250;
  }
  EXPECT_GT(above, 0);
  EXPECT_GT(below, 0);
}

// The farthest region pixel (sampled every 5 px) from its nearest guidepoint [m].
double farthestFromGuidepoints(const Pipeline& p, const std::vector<Guidepoint>& gps) {
  double worst = 0.0;
  for (int y = 0; y < p.region.mask.rows; y += 5)
    for (int x = 0; x < p.region.mask.cols; x += 5) {
      if (!p.region.mask(y, x)) continue;
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& g : gps)
        nearest = std::min(nearest, (g.position_m - p.sketch.frame.pixelCenter(x, y)).norm());
      worst = std::max(worst, nearest);
    }
  return worst;
}

TEST(Guidepoints, AnOpenHallIsCoveredNotOnlyAlongItsSkeleton) {
  const Pipeline p = run(drawHallWithPillars(0), 0.1);  // 60 x 40 m
  GuidepointConfig gc;
  gc.mapping_range_m = 5.0;  // interval 15 m
  const auto covered = sampleGuidepoints(p.skeleton, p.region, p.sketch.frame, gc);
  EXPECT_LE(farthestFromGuidepoints(p, covered), gc.region_cover_factor * gc.intervalM());
  for (const auto& g : covered) {
    const cv::Point px = pixelOf(p.sketch.frame, g.position_m);
    EXPECT_GT(p.region.components(px.y, px.x), 0);
  }
  // Along the medial axis alone the hall's corners are farther than that.
  gc.region_cover_factor = 0.0;
  const auto skeleton_only = sampleGuidepoints(p.skeleton, p.region, p.sketch.frame, gc);
  EXPECT_LT(skeleton_only.size(), covered.size());
  EXPECT_GT(farthestFromGuidepoints(p, skeleton_only),
            GuidepointConfig{}.region_cover_factor * gc.intervalM());
  gc.region_cover_factor = -1.0;
  EXPECT_THROW(gc.validate(), ConfigError);
}

TEST(Guidepoints, LongCorridorIsSampledAtTheInterval) {
  cv::Mat1b img(80, 1000, uint8_t(255));
  cv::rectangle(img, cv::Rect(10, 30, 980, 20), cv::Scalar(0), 2);
  const Pipeline p = run(img, 0.1);  // ~96 m of corridor
  GuidepointConfig gc;
  gc.mapping_range_m = 5.0;  // interval 15 m
  const auto gps = sampleGuidepoints(p.skeleton, p.region, p.sketch.frame, gc);
  ASSERT_GE(gps.size(), 5u);
  ASSERT_LE(gps.size(), 8u);
  std::vector<double> xs;
  for (const auto& g : gps) xs.push_back(g.position_m.x());
  std::sort(xs.begin(), xs.end());
  for (size_t i = 1; i < xs.size(); ++i) {
    EXPECT_GT(xs[i] - xs[i - 1], 0.6 * gc.intervalM());
    EXPECT_LT(xs[i] - xs[i - 1], 1.5 * gc.intervalM());
  }
}

TEST(Guidepoints, EveryArmOfAJunctionGetsOneAndTheJunctionNone) {
  const Pipeline p = run(test::drawPlus(), 0.1);  // arms ~11 m
  GuidepointConfig gc;
  gc.mapping_range_m = 4.0;  // arms are longer than the dead-end minimum (2 m)
  const auto gps = sampleGuidepoints(p.skeleton, p.region, p.sketch.frame, gc);
  ASSERT_EQ(gps.size(), 4u);
  const Eigen::Vector2d centre = p.sketch.frame.pixelCenter(150, 150);
  int north = 0, south = 0, east = 0, west = 0;
  for (const auto& g : gps) {
    const Eigen::Vector2d d = g.position_m - centre;
    EXPECT_GT(d.norm(), 3.0) << "a guidepoint sits on the junction";
    north += d.y() > 3.0;
    south += d.y() < -3.0;
    east += d.x() > 3.0;
    west += d.x() < -3.0;
  }
  EXPECT_EQ(north + south + east + west, 4);
  EXPECT_EQ(north, 1);
  EXPECT_EQ(south, 1);
  EXPECT_EQ(east, 1);
  EXPECT_EQ(west, 1);
}

TEST(Guidepoints, IndependentRegionGetsOne) {
  cv::Mat1b img(200, 300, uint8_t(255));
  cv::rectangle(img, cv::Rect(10, 10, 120, 120), cv::Scalar(0), 2);  // room A
  cv::rectangle(img, cv::Rect(170, 10, 40, 40), cv::Scalar(0), 2);   // closet B, no door
  const Pipeline p = run(img, 0.1);
  ASSERT_EQ(p.region.numComponents(), 2);
  GuidepointConfig gc;
  gc.mapping_range_m = 10.0;
  const auto gps = sampleGuidepoints(p.skeleton, p.region, p.sketch.frame, gc);
  std::set<int> comps;
  for (const auto& g : gps) comps.insert(g.component);
  EXPECT_EQ(comps.size(), 2u);
}

TEST(Guidepoints, Ed21RoomsAndCorridorsAreGuided) {
  SketchLoadConfig lc;
  lc.scale_guess_m_per_px = 0.12;
  const LoadedSketch s = loadSketch(efs::testing::sharedDataPath("ed21/sketch_ed21.png"), lc);
  const TraversableRegion r = extractTraversable(s, {});
  const SkeletonGraph sk = extractSkeleton(r.mask, 0.12, {});
  GuidepointConfig gc;
  gc.mapping_range_m = 5.0;
  const auto gps = sampleGuidepoints(sk, r, s.frame, gc);
  // Places a person expects a guidepoint in (pixel boxes read off the drawing): the east annex,
  // the large north-east hall, the south-west room, the row of north-west offices, the southern
  // row of rooms off the main corridor.
  const std::vector<cv::Rect> expected = {
      {425, 290, 50, 35}, {252, 50, 100, 65}, {78, 400, 78, 35}, {115, 88, 35, 90},
      {150, 88, 35, 90},  {236, 315, 40, 80}, {316, 315, 64, 80}};
  for (const auto& box : expected) {
    bool found = false;
    for (const auto& g : gps) {
      const Eigen::Vector2d px = s.frame.toPixel(g.position_m);
      found = found || box.contains(cv::Point(static_cast<int>(px.x()), static_cast<int>(px.y())));
    }
    EXPECT_TRUE(found) << "no guidepoint in box at " << box;
  }
  // No guidepoint outside the traversable region; none closer than half the mapping range to
  // another; every skeleton pixel is covered within the configured gap.
  for (size_t i = 0; i < gps.size(); ++i) {
    const Eigen::Vector2d px = s.frame.toPixel(gps[i].position_m);
    EXPECT_EQ(r.mask(static_cast<int>(px.y()), static_cast<int>(px.x())), 255);
    for (size_t j = i + 1; j < gps.size(); ++j) {
      EXPECT_GE((gps[i].position_m - gps[j].position_m).norm(), 0.5 * gc.mapping_range_m - 0.2);
    }
  }
}

}  // namespace
}  // namespace efs::prior_map
