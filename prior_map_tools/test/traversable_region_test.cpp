// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/traversable_region.h"

#include <gtest/gtest.h>

#include "efs_common/config_check.h"
#include "efs_common/testing/paths.h"
#include "prior_map_tools/prior_map_error.h"
#include "test_sketches.h"

namespace efs::prior_map {
namespace {

LoadedSketch building(double m_per_px) {
  SketchLoadConfig config;
  config.scale_guess_m_per_px = m_per_px;
  return sketchFromImage(test::drawBuilding(), config, "building");
}

void expectThrowsWith(const LoadedSketch& s, const TraversableConfig& c,
                      const std::string& needle) {
  try {
    extractTraversable(s, c);
    FAIL() << "expected PriorMapError with '" << needle << "'";
  } catch (const PriorMapError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(s.source_path), std::string::npos) << e.what();
  }
}

TEST(TraversableRegion, InteriorIsOneRegionAndOutsideIsExcludedDespiteOuterDoor) {
  // The scale guess may be wrong by a factor of two either way.
  for (double m_per_px : {0.05, 0.1, 0.2}) {
    const TraversableRegion r = extractTraversable(building(m_per_px), {});
    SCOPED_TRACE(m_per_px);
    EXPECT_EQ(r.numComponents(), 1);
    const cv::Point c = test::corridorPixel(), n = test::northRoomPixel(),
                    s = test::southRoomPixel(), o = test::outsidePixel();
    EXPECT_EQ(r.mask(c.y, c.x), 255);
    EXPECT_EQ(r.mask(n.y, n.x), 255);
    EXPECT_EQ(r.mask(s.y, s.x), 255);
    EXPECT_EQ(r.mask(o.y, o.x), 0);
    EXPECT_EQ(r.components(c.y, c.x), r.components(n.y, n.x));
    EXPECT_EQ(r.components(c.y, c.x), r.components(s.y, s.x));
    // Nothing outside the outer wall's rectangle is traversable.
    EXPECT_EQ(cv::countNonZero(r.mask(cv::Rect(0, 0, 48, 300))), 0);
    EXPECT_EQ(cv::countNonZero(r.mask(cv::Rect(0, 0, 400, 48))), 0);
    EXPECT_GT(r.outer_gap_closing_px, 0);
  }
}

TEST(TraversableRegion, RobotClearanceKeepsAwayFromWalls) {
  TraversableConfig c;
  c.robot_radius_m = 0.5;
  const TraversableRegion r = extractTraversable(building(0.1), c);
  // Row 50 is the north wall: rows within 5 px of it are not traversable.
  EXPECT_EQ(cv::countNonZero(r.mask(cv::Rect(60, 51, 200, 4))), 0);
  EXPECT_GT(cv::countNonZero(r.mask(cv::Rect(60, 60, 200, 4))), 0);
}

TEST(TraversableRegion, AllBlackAllWhiteAndTooNarrowAreClearErrors) {
  SketchLoadConfig lc;
  expectThrowsWith(sketchFromImage(cv::Mat1b(50, 50, uint8_t(0)), lc, "black.png"), {},
                   "all black");
  expectThrowsWith(sketchFromImage(cv::Mat1b(50, 50, uint8_t(255)), lc, "white.png"), {},
                   "all white");
  // A closed 4-px-wide corridor: free inside, but too narrow for a 0.5 m robot at 0.1 m/px.
  cv::Mat1b narrow(60, 200, uint8_t(255));
  cv::rectangle(narrow, cv::Rect(10, 20, 180, 6), cv::Scalar(0), 1);
  expectThrowsWith(sketchFromImage(narrow, lc, "narrow.png"), {0.5, 4.0, 0.1},
                   "large enough for the robot");
  // Open lines with nothing enclosed.
  cv::Mat1b lines(100, 100, uint8_t(255));
  cv::line(lines, {10, 10}, {90, 10}, cv::Scalar(0), 1);
  expectThrowsWith(sketchFromImage(lines, lc, "lines.png"), {}, "no traversable region");
}

TEST(TraversableRegion, PartialSketchWithAnOpenOutlineUsesTheInksHull) {
  // Three sides of a 16 m x 10 m hall and a room in one corner: the fourth wall was left out of
  // the drawing (10 m wide: far beyond max_outer_gap_m), so the outline encloses only the room.
  cv::Mat1b partial(140, 200, uint8_t(255));
  cv::line(partial, {20, 20}, {180, 20}, cv::Scalar(0), 2);
  cv::line(partial, {20, 20}, {20, 120}, cv::Scalar(0), 2);
  cv::line(partial, {180, 20}, {180, 120}, cv::Scalar(0), 2);
  SketchLoadConfig lc;
  const TraversableRegion open =
      extractTraversable(sketchFromImage(partial, lc, "partial.png"), {});
  EXPECT_TRUE(open.outer_outline_open);
  EXPECT_GT(open.area_m2, 0.8 * 16.0 * 10.0);  // the hall between the three walls
  EXPECT_EQ(open.mask(70, 100), 255);
  EXPECT_EQ(open.mask(70, 10), 0) << "outside the drawn walls";
  // A closed outline is unaffected.
  cv::Mat1b closed = partial.clone();
  cv::line(closed, {20, 120}, {180, 120}, cv::Scalar(0), 2);
  const TraversableRegion shut = extractTraversable(sketchFromImage(closed, lc, "closed.png"), {});
  EXPECT_FALSE(shut.outer_outline_open);
  EXPECT_EQ(shut.mask(70, 100), 255);
}

TEST(TraversableRegion, AClosetInsideAnOpenOutlineIsNotTheBuilding) {
  // The hall of the test above with a service core drawn in it (a closed 4 x 1.6 m box): the
  // outline is still open, and the box, the one enclosed area, spans a fraction of the strokes.
  cv::Mat1b partial(140, 200, uint8_t(255));
  cv::line(partial, {20, 20}, {180, 20}, cv::Scalar(0), 2);
  cv::line(partial, {20, 20}, {20, 120}, cv::Scalar(0), 2);
  cv::line(partial, {180, 20}, {180, 120}, cv::Scalar(0), 2);
  cv::rectangle(partial, cv::Rect(80, 60, 40, 16), cv::Scalar(0), 2);
  SketchLoadConfig lc;
  const TraversableRegion open = extractTraversable(sketchFromImage(partial, lc, "core.png"), {});
  EXPECT_TRUE(open.outer_outline_open);
  EXPECT_GT(open.area_m2, 0.8 * 16.0 * 10.0 - 4.0 * 1.6);
  EXPECT_EQ(open.mask(100, 100), 255) << "the hall south of the core";
  EXPECT_EQ(open.mask(40, 50), 255) << "the hall north-west of the core";
  // Held to no span, the box is taken for the building, as before.
  TraversableConfig any_span;
  any_span.min_enclosed_span_fraction = 0.0;
  const TraversableRegion boxed =
      extractTraversable(sketchFromImage(partial, lc, "core.png"), any_span);
  EXPECT_FALSE(boxed.outer_outline_open);
  EXPECT_EQ(boxed.mask(100, 100), 0);
  EXPECT_LT(boxed.area_m2, 4.0 * 1.6);
  TraversableConfig absurd;
  absurd.min_enclosed_span_fraction = 1.5;
  EXPECT_THROW(absurd.validate(), ConfigError);
}

TEST(TraversableRegion, HollowPillarsDoNotMakeAClosetSpanTheDrawing) {
  // A 36 x 24 m car park drawn without its south wall, a service core in it, and its pillars
  // drawn as hollow 1 m squares 6 m apart (gaps wider than max_outer_gap_m: they seal nothing).
  // Each pillar encloses a speck (0.36 m^2, below min_region_area_m2) from corner to corner of the
  // hall; the enclosed area that counts is still the core alone.
  cv::Mat1b partial(300, 400, uint8_t(255));
  cv::line(partial, {20, 20}, {380, 20}, cv::Scalar(0), 2);
  cv::line(partial, {20, 20}, {20, 260}, cv::Scalar(0), 2);
  cv::line(partial, {380, 20}, {380, 260}, cv::Scalar(0), 2);
  cv::rectangle(partial, cv::Rect(180, 130, 40, 16), cv::Scalar(0), 2);
  for (int x = 80; x <= 320; x += 60) {
    for (int y = 70; y <= 190; y += 60) {
      if (x >= 170 && x <= 230 && y >= 120 && y <= 156) continue;  // not inside the core
      cv::rectangle(partial, cv::Rect(x, y, 10, 10), cv::Scalar(0), 2);
    }
  }
  SketchLoadConfig lc;
  const TraversableRegion open =
      extractTraversable(sketchFromImage(partial, lc, "pillars.png"), {});
  EXPECT_TRUE(open.outer_outline_open);
  EXPECT_GT(open.area_m2, 0.7 * 36.0 * 24.0);
  EXPECT_EQ(open.mask(230, 230), 255) << "the hall south-east of the core";
  EXPECT_EQ(open.mask(100, 100), 255) << "the hall north-west of the core";
}

TEST(TraversableRegion, PillarsSpanningAnOpenOutlineAreNotTheBuilding) {
  // A room-and-pillar mine drawn without its south and east walls: its 4 x 4 m pillars, each a
  // closed square standing free 7 m apart (beyond max_outer_gap_m), are all the drawing encloses,
  // and they span the hall. Each is larger than min_region_area_m2, so the span rule alone would
  // take them for the mine. The south-east one stands on the edge of the strokes' convex hull.
  cv::Mat1b partial(320, 420, uint8_t(255));
  cv::line(partial, {10, 10}, {410, 10}, cv::Scalar(0), 2);
  cv::line(partial, {10, 10}, {10, 310}, cv::Scalar(0), 2);
  for (int x = 60; x <= 280; x += 110)
    for (int y = 60; y <= 170; y += 110)
      cv::rectangle(partial, cv::Rect(x, y, 40, 40), cv::Scalar(0), 2);
  SketchLoadConfig lc;
  const TraversableRegion open = extractTraversable(sketchFromImage(partial, lc, "mine.png"), {});
  EXPECT_TRUE(open.outer_outline_open);
  EXPECT_EQ(open.numComponents(), 1);
  EXPECT_EQ(open.mask(135, 135), 255) << "the drift between four pillars";
  EXPECT_EQ(open.mask(35, 200), 255) << "along the north wall";
  EXPECT_EQ(open.mask(80, 80), 0) << "inside a pillar";
  EXPECT_EQ(open.mask(190, 300), 0) << "inside the pillar on the hull's edge";
  // One loop drawn alone is still a building (a cave drawn as its outline), pillars or not.
  cv::Mat1b cave(300, 400, uint8_t(255));
  cv::ellipse(cave, cv::Point(200, 150), cv::Size(170, 120), 0, 0, 360, cv::Scalar(0), 2);
  cv::rectangle(cave, cv::Rect(180, 130, 40, 40), cv::Scalar(0), 2);
  const TraversableRegion shut = extractTraversable(sketchFromImage(cave, lc, "cave.png"), {});
  EXPECT_FALSE(shut.outer_outline_open);
  EXPECT_EQ(shut.mask(150, 100), 255);
  EXPECT_EQ(shut.mask(150, 200), 0) << "inside the pillar";
  EXPECT_EQ(shut.mask(10, 10), 0) << "outside the cave";
}

TEST(TraversableRegion, AnOpenOutlineDoesNotSpanTheEmptyPageBetweenItsArms) {
  // Two 6 m drifts meeting in an L (80 x 60 m page), both ends left open: nothing is enclosed.
  // The strokes' convex hull is the whole triangle, with 40 x 40 m of rock inside the L that the
  // drawing never claims; strokes 40 m apart and more do not bound one place.
  cv::Mat1b l_shape(600, 800, uint8_t(255));
  cv::line(l_shape, {20, 20}, {20, 580}, cv::Scalar(0), 2);  // outer walls
  cv::line(l_shape, {20, 580}, {780, 580}, cv::Scalar(0), 2);
  cv::line(l_shape, {80, 20}, {80, 520}, cv::Scalar(0), 2);  // inner walls
  cv::line(l_shape, {80, 520}, {780, 520}, cv::Scalar(0), 2);
  SketchLoadConfig lc;
  const LoadedSketch sketch = sketchFromImage(l_shape, lc, "l_shape.png");
  TraversableConfig near;
  near.open_outline_gap_m = 40.0;
  const TraversableRegion r = extractTraversable(sketch, near);
  EXPECT_TRUE(r.outer_outline_open);
  EXPECT_EQ(r.mask(300, 50), 255) << "in the north-south drift";
  EXPECT_EQ(r.mask(550, 400), 255) << "in the east-west drift";
  EXPECT_EQ(r.mask(300, 300), 0) << "the rock inside the L";
  EXPECT_EQ(r.mask(200, 100), 0) << "beside the drift, in the rock";
  const TraversableRegion whole = extractTraversable(sketch, {});
  EXPECT_EQ(whole.mask(300, 300), 255) << "the hull takes the rock for the inside";
  TraversableConfig absurd;
  absurd.open_outline_gap_m = -1.0;
  EXPECT_THROW(absurd.validate(), ConfigError);
}

// A hall whose outline is drawn closed, with a 4 x 4 m pillar drawn as a closed square standing
// free in it, and a room whose walls join the outline, entered through a door. The pillar's
// inside is rock: no stroke joins its loop to the outline. The room is a place to be.
TEST(TraversableRegion, TheInsideOfAFreeStandingLoopIsSolid) {
  cv::Mat1b hall(300, 400, uint8_t(255));
  cv::rectangle(hall, cv::Rect(20, 20, 360, 260), cv::Scalar(0), 2);
  cv::rectangle(hall, cv::Rect(100, 100, 40, 40), cv::Scalar(0), 2);  // the pillar
  cv::line(hall, {260, 20}, {260, 120}, cv::Scalar(0), 2);            // the room's west wall
  cv::line(hall, {260, 120}, {300, 120}, cv::Scalar(0), 2);           // its south wall,
  cv::line(hall, {330, 120}, {380, 120}, cv::Scalar(0), 2);           // a 3 m door in it
  SketchLoadConfig lc;
  const LoadedSketch sketch = sketchFromImage(hall, lc, "pillar_hall.png");
  const TraversableRegion r = extractTraversable(sketch, {});
  EXPECT_FALSE(r.outer_outline_open);
  EXPECT_EQ(r.numComponents(), 1);
  EXPECT_EQ(r.mask(120, 120), 0) << "inside the pillar";
  EXPECT_EQ(r.mask(60, 320), 255) << "in the room";
  EXPECT_EQ(r.mask(200, 200), 255) << "in the hall";
  EXPECT_EQ(r.components(60, 320), r.components(200, 200));
  // Kept, the pillar's inside is a region of its own, as it was before islands were dropped.
  TraversableConfig keep;
  keep.drop_island_interiors = false;
  const TraversableRegion kept = extractTraversable(sketch, keep);
  EXPECT_EQ(kept.numComponents(), 2);
  EXPECT_EQ(kept.mask(120, 120), 255);
  EXPECT_NE(kept.components(120, 120), kept.components(200, 200));
}

TEST(TraversableRegion, OccupancyGridUnknownIsNotTraversable) {
  cv::Mat1b grid(40, 60, uint8_t(205));
  grid(cv::Rect(10, 10, 40, 20)).setTo(254);
  SketchLoadConfig lc;
  lc.scale_guess_m_per_px = 0.1;
  const TraversableRegion r =
      extractTraversable(sketchFromImage(grid, lc, "grid"), {0.1, 4.0, 0.5});
  EXPECT_EQ(r.mask(5, 5), 0);
  EXPECT_EQ(r.mask(20, 30), 255);
  EXPECT_EQ(cv::countNonZero(r.mask & (grid == 205)), 0);
}

TEST(TraversableRegion, Ed21SketchesGiveTheBuildingInteriorOnly) {
  for (const char* name :
       {"sketch_ed21.png", "sketch_ed21_1.png", "sketch_ed21_2.png", "sketch_ed21_3.png"}) {
    SCOPED_TRACE(name);
    SketchLoadConfig lc;
    lc.scale_guess_m_per_px = 0.12;
    const LoadedSketch s =
        loadSketch(efs::testing::sharedDataPath(std::string("ed21/") + name), lc);
    const TraversableRegion r = extractTraversable(s, {});
    ASSERT_GE(r.numComponents(), 1);
    // The building's rooms and corridors form one connected region: closets drawn without a door
    // are the only other components, and together they are small.
    EXPECT_GT(r.component_area_m2[0], 0.8 * r.area_m2);
    // The page outside the building is excluded: the image corners, and everything outside the
    // bounding box of the drawn walls.
    EXPECT_EQ(r.mask(0, 0), 0);
    EXPECT_EQ(r.mask(r.mask.rows - 1, r.mask.cols - 1), 0);
    const cv::Rect walls = cv::boundingRect(s.wall_mask);
    EXPECT_EQ(cv::countNonZero(r.mask) - cv::countNonZero(r.mask(walls)), 0);
    // The exterior (page area around the building outline) holds no traversable pixel.
    cv::Mat1b outside = ~r.footprint;
    EXPECT_EQ(cv::countNonZero(outside & r.mask), 0);
    EXPECT_GT(cv::countNonZero(outside), 0.1 * outside.total());
  }
}

}  // namespace
}  // namespace efs::prior_map
