// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Bad input never crashes the registration and always leaves a status that says why.
#include <gtest/gtest.h>

#include <limits>

#include "efs_common/config_check.h"
#include "efs_common/testing/config_error.h"
#include "sketch_registration/sketch_registration.h"
#include "sketch_registration/synthetic_scene.h"

namespace efs::registration {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
namespace syn = synthetic;

struct Office {
  Points2d sketch, candidates;
  syn::FloorPlan plan;
};

const Office& office() {
  static const Office o = [] {
    Office x;
    Vector2d lo, hi;
    std::vector<syn::Box> solids;
    x.plan = syn::makeOfficeFloor(&lo, &hi, &solids);
    const syn::Scenario sc = syn::makeScenario(x.plan, solids, lo, hi, Sim2(), {{3, 18}});
    x.sketch = sc.sketch_points_m;
    x.candidates = sc.candidates_m;
    return x;
  }();
  return o;
}

Points3d scanAt(const Vector2d& p) {
  syn::LocalMapSimulator sim(office().plan, syn::LocalMapSimulator::Config{});
  sim.scanAt(p);
  return sim.localMap(p, 40.0);
}

TEST(BadInput, EmptyMap) {
  SketchRegistration reg(SketchRegistration::Config{}, office().sketch, office().candidates);
  const auto& r = reg.addFrame(0.0, {10, 18, 1.5}, {});
  EXPECT_EQ(r.status, RegistrationStatus::kBadInput);
  EXPECT_NE(r.message.find("local map"), std::string::npos) << r.message;
  EXPECT_TRUE(r.hypotheses.empty());
}

TEST(BadInput, ViewWithTooFewWallsIsSaidSoNotCalledAnUnusableMap) {
  // Floor and ceiling all round and a single 1 m wall 10 m off (an aisle whose sides are parked
  // cars): a sound map with walls in too few bearings for a descriptor.
  Points3d map;
  // The floor and ceiling run past the descriptor's range: the view ends nowhere but at the wall.
  for (double x = -45; x <= 45; x += 0.5) {
    for (double y = -45; y <= 45; y += 0.5) {
      map.emplace_back(10 + x, 18 + y, 0.0);
      map.emplace_back(10 + x, 18 + y, 3.0);
    }
  }
  for (double y = -0.5; y <= 0.5; y += 0.1) {
    for (double z = 0; z <= 3.0; z += 0.1) map.emplace_back(20.0, 18 + y, z);
  }
  SketchRegistration reg(SketchRegistration::Config{}, office().sketch, office().candidates);
  const auto& r = reg.addFrame(0.0, {10, 18, 1.5}, map);
  EXPECT_EQ(r.status, RegistrationStatus::kBadInput);
  EXPECT_NE(r.message.find("too few walls in view"), std::string::npos) << r.message;
  EXPECT_EQ(r.message.find("unusable"), std::string::npos) << r.message;
  EXPECT_TRUE(r.hypotheses.empty());
}

TEST(BadInput, NanLadenMap) {
  SketchRegistration reg(SketchRegistration::Config{}, office().sketch, office().candidates);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Points3d all_nan(1000, Vector3d(nan, 1.0, nan));
  auto r = reg.addFrame(0.0, {10, 18, 1.5}, all_nan);
  EXPECT_EQ(r.status, RegistrationStatus::kBadInput);
  EXPECT_NE(r.message.find("non-finite"), std::string::npos) << r.message;
  // NaNs mixed into a good map are dropped: the frame is used.
  Points3d mixed = scanAt({10, 18});
  for (size_t i = 0; i < mixed.size(); i += 3) mixed[i].x() = nan;
  mixed.push_back(Vector3d(std::numeric_limits<double>::infinity(), 0, 0));
  r = reg.addFrame(1.0, {10, 18, 1.5}, mixed);
  EXPECT_EQ(r.status, RegistrationStatus::kTooFewFrames) << r.message;
  EXPECT_FALSE(r.last_frame.candidates.empty());
}

TEST(BadInput, NonFiniteRobotOrTimeAndTimeGoingBack) {
  SketchRegistration reg(SketchRegistration::Config{}, office().sketch, office().candidates);
  const Points3d map = scanAt({10, 18});
  EXPECT_EQ(reg.addFrame(0.0, {std::nan(""), 18, 1.5}, map).status, RegistrationStatus::kBadInput);
  EXPECT_EQ(reg.addFrame(std::nan(""), {10, 18, 1.5}, map).status, RegistrationStatus::kBadInput);
  EXPECT_EQ(reg.addFrame(5.0, {10, 18, 1.5}, map).status, RegistrationStatus::kTooFewFrames);
  const auto& r = reg.addFrame(5.0, {10, 18, 1.5}, map);
  EXPECT_EQ(r.status, RegistrationStatus::kBadInput);
  EXPECT_NE(r.message.find("time"), std::string::npos);
}

TEST(BadInput, SketchWithoutCandidates) {
  {
    SketchRegistration reg(SketchRegistration::Config{}, office().sketch, {});
    const auto& r = reg.addFrame(0.0, {10, 18, 1.5}, scanAt({10, 18}));
    EXPECT_EQ(r.status, RegistrationStatus::kNoCandidates);
    EXPECT_NE(r.message.find("0 candidates"), std::string::npos) << r.message;
  }
  {
    // Candidates but no boundary: no usable descriptor anywhere.
    SketchRegistration reg(SketchRegistration::Config{}, {}, office().candidates);
    EXPECT_EQ(reg.addFrame(0.0, {10, 18, 1.5}, scanAt({10, 18})).status,
              RegistrationStatus::kNoCandidates);
  }
  {
    // Non-finite candidates are dropped.
    Points2d c = {Vector2d(std::nan(""), 1.0), Vector2d(1.0, std::nan(""))};
    SketchRegistration reg(SketchRegistration::Config{}, office().sketch, c);
    EXPECT_EQ(reg.database().size(), 0u);
    EXPECT_EQ(reg.addFrame(0.0, {10, 18, 1.5}, scanAt({10, 18})).status,
              RegistrationStatus::kNoCandidates);
  }
}

TEST(BadInput, OdometryJumpRestartsVerification) {
  SketchRegistration reg(SketchRegistration::Config{}, office().sketch, office().candidates);
  EXPECT_EQ(reg.addFrame(0.0, {10, 18, 1.5}, scanAt({10, 18})).status,
            RegistrationStatus::kTooFewFrames);
  EXPECT_EQ(reg.addFrame(5.0, {20, 18, 1.5}, scanAt({20, 18})).status,
            RegistrationStatus::kTooFewFrames);
  EXPECT_EQ(reg.verifier().numFrames(), 2u);
  // 500 m in 5 s.
  const auto& r = reg.addFrame(10.0, {520, 18, 1.5}, scanAt({30, 18}));
  EXPECT_EQ(r.status, RegistrationStatus::kOdometryJump);
  EXPECT_NE(r.message.find("m/s"), std::string::npos);
  EXPECT_EQ(reg.verifier().numFrames(), 0u);
  EXPECT_TRUE(r.hypotheses.empty());
}

TEST(BadInput, FramesTooCloseAreNotCountedTwice) {
  SketchRegistration reg(SketchRegistration::Config{}, office().sketch, office().candidates);
  const Points3d map = scanAt({10, 18});
  reg.addFrame(0.0, {10, 18, 1.5}, map);
  const auto& r = reg.addFrame(5.0, {10.2, 18, 1.5}, map);  // hovering
  EXPECT_FALSE(r.last_frame.used_for_verification);
  EXPECT_EQ(reg.verifier().numFrames(), 1u);
  EXPECT_EQ(r.status, RegistrationStatus::kTooFewFrames);
}

TEST(BadInput, ConfigValidationNamesTheKey) {
  auto expectKey = [](SketchRegistration::Config c, const std::string& key) {
    efs::testing::expectConfigErrorNaming([&] { c.validate(); }, key);
  };
  SketchRegistration::Config c;
  c.scale_guess = 0.0;
  expectKey(c, "scale_guess");
  c = {};
  c.retrieval.eta = 2.0;
  expectKey(c, "eta");
  c = {};
  c.icp.max_stretch = 0.9;  // a stretch is >= 1 by definition
  expectKey(c, "max_stretch");
  c = {};
  c.stretch_min_fitness_gain = 1.5;
  expectKey(c, "stretch_min_fitness_gain");
  c = {};
  c.confidence_tau = -1.0;
  expectKey(c, "confidence_tau");
  c = {};
  c.verifier.n_f = 2;
  expectKey(c, "n_f");
  c = {};
  c.screen_points = -1;
  expectKey(c, "screen_points");
  c = {};
  c.screen_iterations = 0;
  expectKey(c, "screen_iterations");
  c = {};
  c.descriptor.mirror_score_margin = -0.1;
  expectKey(c, "mirror_score_margin");
  c = {};
  c.mirror_dominance_coverage = 1.5;
  expectKey(c, "mirror_dominance_coverage");
  c = {};
  c.descriptor.num_bins = 91;  // not divisible by the coarse shift factor
  expectKey(c, "coarse_shift_factor");
  c = {};
  c.observation.slice_min_dz_m = c.observation.slice_max_dz_m;
  expectKey(c, "slice_min_dz_m");
  c = {};
  c.observation.column_cell_m = 0.0;
  expectKey(c, "column_cell_m");
  c = {};
  c.observation.wall_max_gap_m = -1.0;
  expectKey(c, "wall_max_gap_m");
  c = {};
  c.observation.wall_min_height_m = std::numeric_limits<double>::quiet_NaN();
  expectKey(c, "wall_min_height_m");
  c = {};
  c.observation.wall_continuation_m = 0.05;  // inside the continuation's own lower bound
  expectKey(c, "wall_continuation_m");
  c = {};
  c.observation.wall_top_clear_m = std::numeric_limits<double>::infinity();
  expectKey(c, "wall_top_clear_m");
  c = {};
  c.kept_fitness_threshold_m = 0.5 * c.fitness_threshold_m;
  expectKey(c, "kept_fitness_threshold_m");
  c = {};
  c.kept_min_inlier_ratio = c.icp.min_inlier_ratio + 0.1;
  expectKey(c, "kept_min_inlier_ratio");
  c = {};
  c.kept_min_inside_ratio = c.icp.min_inside_ratio + 0.1;
  expectKey(c, "kept_min_inside_ratio");
  c = {};
  c.kept_min_inside_ratio = -0.1;
  expectKey(c, "kept_min_inside_ratio");
  c = {};
  c.kept_drawing_reach_m = -1.0;
  expectKey(c, "kept_drawing_reach_m");
  c = {};
  c.kept_drawing_reach_m = std::numeric_limits<double>::quiet_NaN();
  expectKey(c, "kept_drawing_reach_m");
  c = {};
  c.kept_drawing_reach_min_age_frames = -1;
  expectKey(c, "kept_drawing_reach_min_age_frames");
  c = {};
  c.settled_coverage = 1.5;
  expectKey(c, "settled_coverage");
  c = {};
  c.coverage_weight_m = -1.0;
  expectKey(c, "coverage_weight_m");
  c = {};
  c.icp.max_iterations = 0;
  expectKey(c, "max_iterations");
  // The constructor validates too.
  c = {};
  c.fitness_threshold_m = 0.0;
  EXPECT_THROW(SketchRegistration(c, {}, {}), ConfigError);
  // Paper defaults.
  const SketchRegistration::Config d;
  EXPECT_EQ(d.descriptor.num_bins, 90);
  EXPECT_EQ(d.descriptor.num_fft, 10);
  EXPECT_DOUBLE_EQ(d.d_gap_m, 1.0);
  EXPECT_DOUBLE_EQ(d.confidence_tau, 0.3);
  EXPECT_EQ(d.verifier.n_f, 4);
  EXPECT_DOUBLE_EQ(d.retrieval.weights.alpha_cos, 0.4);
  EXPECT_DOUBLE_EQ(d.retrieval.weights.alpha_fft, 0.4);
  EXPECT_DOUBLE_EQ(d.retrieval.weights.alpha_cv, 0.2);
  EXPECT_DOUBLE_EQ(d.verifier.lambda.lambda_t, 5.0);
  EXPECT_DOUBLE_EQ(d.verifier.lambda.lambda_r, 10.0);
  EXPECT_DOUBLE_EQ(d.verifier.lambda.lambda_s, 1.0);
  EXPECT_DOUBLE_EQ(d.retrieval.eta, 0.05);
}

}  // namespace
}  // namespace efs::registration
