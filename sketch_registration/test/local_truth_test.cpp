// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/local_truth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "efs_common/angles.h"

namespace efs::registration {
namespace {

using Eigen::Vector2d;

// A drawing of a 200 x 20 m hall whose west half was drawn with one similarity and whose east
// half with another (5 % larger, turned 2 deg, shifted): no single similarity is true everywhere.
struct TwoPartDrawing {
  Sim2 T_sketch_world_west{0.3, 0.5, Vector2d(4.0, -2.0)};
  Sim2 T_sketch_world_east{0.3 + 2.0 * M_PI / 180.0, 0.525, Vector2d(1.0, -3.0)};
  Points2d world_m, sketch_m;

  TwoPartDrawing() {
    for (double x = 0.0; x <= 200.0; x += 1.0) {
      for (double y : {0.0, 20.0}) {
        world_m.emplace_back(x, y);
        const Sim2& T = x < 100.0 ? T_sketch_world_west : T_sketch_world_east;
        sketch_m.push_back(T.apply(world_m.back()));
      }
    }
  }
};

TEST(LocalTruth, FitsTheSimilarityOfThePartSeen) {
  const TwoPartDrawing d;
  LocalTruth truth(d.world_m, d.sketch_m, 30.0, false);
  EXPECT_FALSE(truth.fit());
  EXPECT_TRUE(std::isnan(truth.placementRms(Sim2())));

  truth.observeFrom({20.0, 10.0});
  truth.observeFrom({50.0, 10.0});
  ASSERT_TRUE(truth.fit());
  const Sim2 west = d.T_sketch_world_west.inverse();
  const Sim2& fit = truth.fit()->T_world_sketch;
  EXPECT_NEAR(fit.scale, west.scale, 1e-9);
  EXPECT_NEAR(angleDiff(fit.yaw_rad, west.yaw_rad), 0.0, 1e-9);
  EXPECT_NEAR((fit.t_m - west.t_m).norm(), 0.0, 1e-6);
  EXPECT_NEAR(truth.fit()->rms_residual_m, 0.0, 1e-9);
  EXPECT_NEAR(truth.placementRms(west), 0.0, 1e-9);
  // The east half's similarity is metres off over the west half.
  EXPECT_GT(truth.placementRms(d.T_sketch_world_east.inverse()), 2.0);

  // Seeing the east half too: the fit is a compromise that fits neither half exactly.
  truth.observeFrom({150.0, 10.0});
  ASSERT_TRUE(truth.fit());
  EXPECT_GT(truth.fit()->rms_residual_m, 0.5);
  EXPECT_GT(truth.placementRms(west), 0.5);
}

TEST(LocalTruth, SeesNothingFromAfarOrFromNowhere) {
  const TwoPartDrawing d;
  LocalTruth truth(d.world_m, d.sketch_m, 10.0, false);
  truth.observeFrom({100.0, 500.0});
  truth.observeFrom({std::nan(""), 10.0});
  EXPECT_EQ(truth.seenCount(), 0u);
  EXPECT_FALSE(truth.fit());
}

TEST(LocalTruth, MirroredDrawingIsFitAsAMirror) {
  const TwoPartDrawing d;
  const Sim2 mirror(0.7, 2.0, Vector2d(3.0, 1.0), true);
  Points2d sketch_m;
  for (const Vector2d& p : d.world_m) sketch_m.push_back(mirror.inverse().apply(p));
  LocalTruth truth(d.world_m, sketch_m, 30.0, true);
  truth.observeFrom({100.0, 10.0});
  ASSERT_TRUE(truth.fit());
  EXPECT_TRUE(truth.fit()->T_world_sketch.reflected);
  EXPECT_NEAR(truth.placementRms(mirror), 0.0, 1e-6);
}

TEST(LocalTruth, AStretchedDrawingIsFitWithTheStretchWhereTheRegistrationHasOne) {
  const TwoPartDrawing d;
  Sim2 T_world_sketch(0.7, 2.0, Vector2d(3.0, 1.0));
  T_world_sketch.stretch = 1.07;
  T_world_sketch.stretch_axis_rad = 0.3;
  Points2d sketch_m;
  for (const Vector2d& p : d.world_m) sketch_m.push_back(T_world_sketch.inverse().apply(p));
  LocalTruth stretched(d.world_m, sketch_m, 120.0, false, 1.1);
  LocalTruth similarity(d.world_m, sketch_m, 120.0, false);
  for (LocalTruth* t : {&stretched, &similarity}) t->observeFrom({100.0, 10.0});
  ASSERT_TRUE(stretched.fit() && similarity.fit());
  EXPECT_NEAR(stretched.placementRms(T_world_sketch), 0.0, 1e-6);
  EXPECT_NEAR(stretched.fit()->T_world_sketch.stretch, 1.07, 1e-6);
  EXPECT_TRUE(similarity.fit()->T_world_sketch.isSimilarity());
  EXPECT_GT(similarity.fit()->rms_residual_m, 1.0);
}

TEST(LocalTruth, BadArgumentsAreNamed) {
  const TwoPartDrawing d;
  Points2d fewer = d.sketch_m;
  fewer.pop_back();
  EXPECT_THROW(LocalTruth(d.world_m, fewer, 30.0, false), std::invalid_argument);
  EXPECT_THROW(LocalTruth(d.world_m, d.sketch_m, 0.0, false), std::invalid_argument);
  EXPECT_THROW(LocalTruth(d.world_m, d.sketch_m, std::nan(""), false), std::invalid_argument);
  EXPECT_THROW(LocalTruth(d.world_m, d.sketch_m, 30.0, false, 0.9), std::invalid_argument);
}

}  // namespace
}  // namespace efs::registration
