// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/world_sketch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <opencv2/core.hpp>

#include "efs_common/config_check.h"
#include "efs_common/testing/paths.h"
#include "marsim_worlds/seeded_random.h"
#include "marsim_worlds/world_generators.h"
#include "marsim_worlds/world_importers.h"

namespace efs::sim {
namespace {

// Saves and reloads a sketch so that the checks go through the sidecar file, as an evaluator would.
Sketch roundTrip(const Sketch& sk, const std::string& name) {
  const std::string png = efs::testing::testOutputDir() + "/" + name + ".png";
  saveSketch(sk, png);
  return loadSketch(png);
}

// Wall surface points found by horizontal rays from free points of the world (independent of how
// the sketch finds walls). With `outline`, each direction is cast from a column of heights and
// the farthest return kept: in a cave the drawing is the passage's outline, its widest extent.
std::vector<Eigen::Vector2d> rayWallHits(const VoxelWorld& w, int origins, uint64_t seed,
                                         bool outline = false) {
  SeededRandom rng(seed);
  std::vector<Eigen::Vector2d> hits;
  const Eigen::AlignedBox3d b = w.bounds();
  // Buildings: near the top of the sketch band, above parked cars (which are not drawn).
  const double z = outline ? w.start_poses.front().position_m.z() : w.sketch_band.z_max_m - 0.1;
  int tried = 0;
  Eigen::Vector3d start = w.start_poses.front().position_m;
  start.z() = z;
  std::vector<Eigen::Vector3d> starts{start};
  while (static_cast<int>(starts.size()) < origins && tried++ < 100000) {
    const Eigen::Vector3d p(rng.uniform(b.min().x(), b.max().x()),
                            rng.uniform(b.min().y(), b.max().y()), z);
    if (!w.collides(p, 0.5)) starts.push_back(p);
  }
  for (const auto& o : starts) {
    for (int k = 0; k < 90; ++k) {
      const double a = 2.0 * M_PI * k / 90.0;
      const Eigen::Vector3d d(std::cos(a), std::sin(a), 0.0);
      float r = w.castRay(o, d, 40.0);
      for (double dz = -12.0; outline && dz <= 12.0; dz += 0.25) {
        const Eigen::Vector3d oz = o + Eigen::Vector3d(0, 0, dz);
        if (w.occupiedAt(oz) || !w.bounds().contains(oz)) continue;
        // Only heights reachable straight up or down from the origin count (same passage).
        if (w.castRay(o, Eigen::Vector3d(0, 0, dz > 0 ? 1 : -1), 40.0) < std::abs(dz)) continue;
        const float rz = w.castRay(oz, d, 40.0);
        if (std::isfinite(rz) && (!std::isfinite(r) || rz > r)) r = rz;
      }
      // Step a hair into the wall so the point lies inside the wall's cell, not on its face.
      if (std::isfinite(r)) hits.push_back((o + d * (r + 0.01)).head<2>());
    }
  }
  return hits;
}

double inkFraction(const Sketch& sk, const std::vector<Eigen::Vector2d>& pts_world,
                   int tolerance_px = 0) {
  int ink = 0;
  for (const auto& p : pts_world) {
    const Eigen::Vector2d uv = sk.worldToPixel(p);
    bool hit = false;
    for (int dv = -tolerance_px; dv <= tolerance_px && !hit; ++dv)
      for (int du = -tolerance_px; du <= tolerance_px && !hit; ++du)
        hit = sk.inkAt(uv + Eigen::Vector2d(du, dv));
    ink += hit;
  }
  return pts_world.empty() ? 0.0 : static_cast<double>(ink) / pts_world.size();
}

std::vector<VoxelWorld> testWorlds() {
  std::vector<VoxelWorld> worlds;
  for (WorldKind k :
       {WorldKind::kGarage, WorldKind::kIndoor, WorldKind::kSimpleCave, WorldKind::kSubtCave}) {
    worlds.push_back(generateWorld(k, WorldSize::kSmall, 3, 0.15));
  }
  ImportConfig ic;
  ic.resolution_m = 0.1;
  worlds.push_back(importSdfWorld(efs::testing::sharedDataPath("ed21/ed21.world"), ic));
  return worlds;
}

TEST(WorldSketch, PreciseSketchWallsLandOnInkThroughTheSidecar) {
  SketchConfig cfg;
  cfg.seed = 11;
  for (const VoxelWorld& w : testWorlds()) {
    SCOPED_TRACE(w.name);
    const Sketch drawn = drawSketch(w, SketchVariant::kPrecise, cfg);
    const Sketch sk = roundTrip(drawn, w.name + "_precise");
    // The sketch is unaligned: rotated, offset and at its own pixel size.
    EXPECT_GE(sk.trueMetresPerPixel(), cfg.min_true_mpp - 1e-12);
    EXPECT_LE(sk.trueMetresPerPixel(), cfg.max_true_mpp + 1e-12);
    // World walls (the drawing's definition) through the sidecar transform: all on ink.
    EXPECT_GE(inkFraction(sk, wallPoints(w, w.sketch_band)), 0.99);
    // Wall surfaces found by ray casting: on ink too.
    const bool cave = w.name.find("cave") != std::string::npos;
    const std::vector<Eigen::Vector2d> hits = rayWallHits(w, 20, 5, cave);
    ASSERT_GT(hits.size(), 500u);
    EXPECT_GE(inkFraction(sk, hits, cave ? 1 : 0), 0.95);
    // And the paper stays mostly white: a line drawing, not a filled plan.
    EXPECT_GT(cv::countNonZero(sk.image) / static_cast<double>(sk.image.total()), 0.75);
  }
}

TEST(WorldSketch, VariantsDifferAsDescribed) {
  const VoxelWorld w = generateWorld(WorldKind::kIndoor, WorldSize::kSmall, 3, 0.15);
  const std::vector<Eigen::Vector2d> walls = wallPoints(w, w.sketch_band);
  SketchConfig cfg;
  cfg.seed = 4;
  cfg.partial_regions = 1;
  cfg.partial_region_fraction = 0.2;
  const Sketch partial = roundTrip(drawSketch(w, SketchVariant::kPartial, cfg), "indoor_partial");
  const double kept = inkFraction(partial, walls);
  EXPECT_LT(kept, 0.95);  // a region is missing
  EXPECT_GT(kept, 0.4);   // but most of it is there
  // The region around the start is kept, so that registration from the start is possible.
  EXPECT_TRUE(partial.inkAt(partial.worldToPixel(rayWallHits(w, 1, 1).front())) ||
              partial.inkAt(partial.worldToPixel(rayWallHits(w, 1, 1)[1])));

  const Sketch deformed =
      roundTrip(drawSketch(w, SketchVariant::kDeformed, cfg), "indoor_deformed");
  const double exact = inkFraction(deformed, walls);
  const double near = inkFraction(deformed, walls, 8);
  EXPECT_LT(exact, 0.9);  // walls moved: a non-rigid warp and jitter
  EXPECT_GT(near, 0.9);   // but not far: the similarity in the sidecar is still the best one

  SketchConfig plain = cfg;
  const Sketch scaled = drawSketch(w, SketchVariant::kScaled, plain);
  EXPECT_LE(scaled.trueMetresPerPixel(), cfg.max_true_mpp / cfg.scaled_factor + 1e-12);
  EXPECT_GE(inkFraction(scaled, walls), 0.99);
}

TEST(WorldSketch, DrawnWallsPairEachWorldWallWithItsInk) {
  const VoxelWorld w = generateWorld(WorldKind::kIndoor, WorldSize::kSmall, 3, 0.15);
  const size_t num_walls = wallPoints(w, w.sketch_band).size();
  SketchConfig cfg;
  cfg.seed = 4;
  cfg.partial_regions = 1;
  cfg.partial_region_fraction = 0.2;
  const auto onInk = [](const Sketch& sk, const DrawnWallPoint& d, int tolerance_px) {
    const Eigen::Vector2d uv = sk.sketchToPixel(d.sketch_m);
    for (int dv = -tolerance_px; dv <= tolerance_px; ++dv)
      for (int du = -tolerance_px; du <= tolerance_px; ++du)
        if (sk.inkAt(uv + Eigen::Vector2d(du, dv))) return true;
    return false;
  };

  const Sketch precise = drawSketch(w, SketchVariant::kPrecise, cfg);
  ASSERT_EQ(precise.drawn_walls.size(), num_walls);
  for (const DrawnWallPoint& d : precise.drawn_walls) {
    // Undeformed: the sidecar similarity is the whole story.
    ASSERT_LT((precise.T_world_sketch.apply(d.sketch_m) - d.world_m).norm(), 1e-9);
    ASSERT_TRUE(onInk(precise, d, 0));
  }

  const Sketch partial = drawSketch(w, SketchVariant::kPartial, cfg);
  EXPECT_LT(partial.drawn_walls.size(), 0.95 * num_walls);  // only what was drawn
  EXPECT_GT(partial.drawn_walls.size(), 0.4 * num_walls);

  const Sketch deformed = drawSketch(w, SketchVariant::kDeformed, cfg);
  ASSERT_EQ(deformed.drawn_walls.size(), num_walls);
  int on_ink = 0, moved = 0;
  double worst_m = 0.0;
  for (const DrawnWallPoint& d : deformed.drawn_walls) {
    // The pair is where the line went before the tremor (jitter_px 0.7 < 1 px).
    on_ink += onInk(deformed, d, 1);
    const double off_m = (deformed.T_world_sketch.apply(d.sketch_m) - d.world_m).norm();
    moved += off_m > 0.05;
    worst_m = std::max(worst_m, off_m);
  }
  EXPECT_GT(on_ink, 0.99 * num_walls);
  // The warp the sidecar leaves out: most points moved, by no more than the warp's bound plus
  // the anisotropy over the world's half-extent (about 25 m for the small indoor world).
  EXPECT_GT(moved, 0.8 * num_walls);
  EXPECT_LT(worst_m, cfg.deform_max_m + cfg.anisotropy * 30.0);
}

TEST(WorldSketch, SameSeedSameDrawing) {
  const VoxelWorld w = generateWorld(WorldKind::kSubtCave, WorldSize::kSmall, 3, 0.2);
  SketchConfig cfg;
  cfg.seed = 9;
  for (SketchVariant v : {SketchVariant::kPrecise, SketchVariant::kPartial,
                          SketchVariant::kDeformed, SketchVariant::kScaled}) {
    const Sketch a = drawSketch(w, v, cfg), b = drawSketch(w, v, cfg);
    ASSERT_EQ(a.image.size(), b.image.size());
    EXPECT_EQ(cv::norm(a.image, b.image, cv::NORM_INF), 0.0);
    EXPECT_EQ(a.T_world_sketch.yaw_rad, b.T_world_sketch.yaw_rad);
  }
  SketchConfig other = cfg;
  other.seed = 10;
  EXPECT_NE(drawSketch(w, SketchVariant::kPrecise, cfg).T_world_sketch.yaw_rad,
            drawSketch(w, SketchVariant::kPrecise, other).T_world_sketch.yaw_rad);
}

TEST(WorldSketch, PixelConventionIsBottomLeftOrigin) {
  Sketch sk;
  sk.image = cv::Mat(100, 200, CV_8UC1, cv::Scalar(255));
  sk.metres_per_pixel = 0.5;
  // The bottom-left pixel's centre is (0.25, 0.25); the top-left pixel's is (0.25, 49.75).
  EXPECT_TRUE(sk.pixelToSketch({0, 99}).isApprox(Eigen::Vector2d(0.25, 0.25)));
  EXPECT_TRUE(sk.pixelToSketch({0, 0}).isApprox(Eigen::Vector2d(0.25, 49.75)));
  EXPECT_TRUE(sk.sketchToPixel({0.25, 0.25}).isApprox(Eigen::Vector2d(0.5, 99.5)));
  sk.T_world_sketch = Sim2(M_PI / 2, 2.0, Eigen::Vector2d(10, 0));
  // p_world = 2 R(90 deg) p_sketch + t
  const Eigen::Vector2d w = sk.T_world_sketch.apply(sk.pixelToSketch({0, 99}));
  EXPECT_TRUE(w.isApprox(Eigen::Vector2d(10 - 0.5, 0.5)));
  EXPECT_TRUE(sk.worldToPixel(w).isApprox(Eigen::Vector2d(0.5, 99.5)));
}

TEST(WorldSketch, BadSidecarAndConfigAreNamed) {
  const VoxelWorld w = generateWorld(WorldKind::kGarage, WorldSize::kSmall, 1, 0.2);
  const Sketch sk = drawSketch(w, SketchVariant::kPrecise, SketchConfig());
  const std::string png = efs::testing::testOutputDir() + "/bad_sidecar.png";
  const std::string yaml = saveSketch(sk, png);
  {
    std::ifstream in(yaml);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto pos = text.find("  scale:");
    text.replace(pos, text.find('\n', pos) - pos, "  scale: banana");
    std::ofstream(yaml) << text;
  }
  try {
    loadSketch(png);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'scale'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bad_sidecar.yaml"), std::string::npos) << e.what();
  }
  std::ofstream(yaml) << "variant: precise\n";
  try {
    loadSketch(png);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("lacks key"), std::string::npos) << e.what();
  }
  EXPECT_THROW(loadSketch(efs::testing::testOutputDir() + "/no_such_sketch.png"),
               std::runtime_error);
  SketchConfig bad;
  bad.max_true_mpp = 0.01;  // below min_true_mpp
  try {
    drawSketch(w, SketchVariant::kPrecise, bad);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("max_true_mpp"), std::string::npos);
  }
  EXPECT_THROW(parseSketchVariant("blurry"), std::invalid_argument);
}

}  // namespace
}  // namespace efs::sim
