// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/geo_context.h"

#include <gtest/gtest.h>

#include <random>

#include "efs_common/config_check.h"
#include "sketch_registration/hpr.h"
#include "sketch_registration/synthetic_scene.h"

namespace efs::registration {
namespace {

using Eigen::Vector2d;

Points2d officePoints() { return synthetic::samplePlan(synthetic::makeOfficeFloor(), 0.1); }

Points2d rotatedAbout(const Points2d& pts, const Vector2d& center, double yaw_rad, bool mirror) {
  const Sim2 T(yaw_rad, 1.0, Vector2d::Zero(), mirror);
  Points2d out;
  for (const auto& p : pts) out.push_back(center + T.apply(p - center));
  return out;
}

TEST(Hpr, WallBehindAWallIsHidden) {
  Points2d pts;
  for (double y = -5; y <= 5; y += 0.1) {
    pts.emplace_back(3.0, y);  // front wall
    pts.emplace_back(6.0, y);  // hidden behind it
  }
  pts.emplace_back(-4.0, 0.0);  // alone behind the viewpoint: visible
  HprConfig config;
  const Points2d visible = hiddenPointRemoval(pts, Vector2d::Zero(), config);
  int front = 0, back = 0, behind = 0;
  for (const auto& p : visible) {
    front += p.x() == 3.0;
    behind += p.x() == -4.0;
    // Far-wall points outside the front wall's angular extent (|y| > 10) do not exist here.
    back += p.x() == 6.0;
  }
  EXPECT_EQ(front, 101);
  EXPECT_EQ(behind, 1);
  EXPECT_EQ(back, 0);
}

TEST(Hpr, SparsePointsCloseByStillOcclude) {
  // Wall at 1 m sampled every 0.2 m: each point must cover its angular gap.
  Points2d pts;
  for (double y = -1.0; y <= 1.0; y += 0.2) pts.emplace_back(1.0, y);
  for (double y = -1.0; y <= 1.0; y += 0.05) pts.emplace_back(8.0, y);
  HprConfig config;
  config.point_radius_m = 0.1;
  for (const auto& p : hiddenPointRemoval(pts, Vector2d::Zero(), config)) EXPECT_LT(p.x(), 2.0);
}

TEST(GeoContext, RotatedSceneIsAColumnShift) {
  DescriptorConfig config;
  const Points2d pts = officePoints();
  const Vector2d view(25.0, 18.0);
  const GeoContext d0 = computeGeoContext(pts, view, config);
  ASSERT_TRUE(d0.valid);
  const int n = config.num_bins;
  for (int shift : {1, 7, 45, 83}) {
    const double yaw = 2.0 * M_PI * shift / n;
    const GeoContext d1 = computeGeoContext(rotatedAbout(pts, view, yaw, false), view, config);
    // World direction theta + yaw holds what the original had at theta: d1[i + shift] = d0[i].
    int close = 0;
    for (int i = 0; i < n; ++i)
      close += std::abs(d1.range_m[(i + shift) % n] - d0.range_m[i]) < 0.05;
    EXPECT_GE(close, n - 2) << "shift " << shift;
    const ShiftMatch m = bestColumnShift(d0, d1, false);
    EXPECT_EQ(m.shift, shift);
    EXPECT_NEAR(m.yaw_rad, std::remainder(yaw, 2 * M_PI), 1e-9);
    EXPECT_GT(m.score, 0.995);
    const ShiftMatch fast = bestColumnShiftCoarseToFine(d0, ShiftTables(d1), false, 3);
    EXPECT_EQ(fast.shift, shift);
    // Shift-invariant parts are unchanged by the rotation.
    EXPECT_GT(fftSimilarity(d0, d1), 0.999);
    EXPECT_GT(cvSimilarity(d0, d1), 0.99);
  }
}

TEST(GeoContext, RefiningNearAShiftSearchesOnlyWithinTheHalfWidth) {
  DescriptorConfig config;
  const Points2d pts = officePoints();
  const Vector2d view(25.0, 18.0);
  const int n = config.num_bins;
  const GeoContext d0 = computeGeoContext(pts, view, config);
  const GeoContext d1 =
      computeGeoContext(rotatedAbout(pts, view, 2.0 * M_PI * 45 / n, false), view, config);
  const ShiftTables tables(d1);
  const ShiftMatch full = bestColumnShift(d0, d1, true);
  ASSERT_EQ(full.shift, 45);
  const ShiftMatch near = refineShifts(d0, tables, {43}, 2);
  EXPECT_EQ(near.shift, 45);
  EXPECT_FALSE(near.reversed);
  EXPECT_EQ(near.score, full.score);
  EXPECT_EQ(shiftCode(near, n), 45);
  // Out of reach of the true shift: a worse one, still in the window.
  const ShiftMatch far = refineShifts(d0, tables, {40}, 2);
  EXPECT_LE(std::abs(far.shift - 40), 2);
  EXPECT_LT(far.score, full.score);
  // Wrapping around bin 0, and a mirrored centre stays mirrored.
  const GeoContext d2 =
      computeGeoContext(rotatedAbout(pts, view, 2.0 * M_PI * 1 / n, false), view, config);
  EXPECT_EQ(refineShifts(d0, ShiftTables(d2), {n - 1}, 2).shift, 1);
  const ShiftMatch mirrored = refineShifts(d0, tables, {n + 45}, 2);
  EXPECT_TRUE(mirrored.reversed);
  EXPECT_EQ(shiftCode(mirrored, n), n + mirrored.shift);
}

TEST(GeoContext, MirroredSceneMatchesReversed) {
  DescriptorConfig config;
  const Points2d pts = officePoints();
  const Vector2d view(50.0, 25.0);
  const GeoContext d0 = computeGeoContext(pts, view, config);
  const double yaw = 2.0 * M_PI * 20 / config.num_bins;
  const GeoContext d1 = computeGeoContext(rotatedAbout(pts, view, yaw, true), view, config);
  const ShiftMatch m = bestColumnShift(d0, d1, true);
  EXPECT_TRUE(m.reversed);
  EXPECT_EQ(m.shift, 20);
  EXPECT_GT(m.score, 0.99);
  const ShiftMatch fast = bestColumnShiftCoarseToFine(d0, ShiftTables(d1), true, 3);
  EXPECT_TRUE(fast.reversed);
  EXPECT_EQ(fast.shift, 20);
  // Without the mirrored search the score is lower.
  EXPECT_LT(bestColumnShift(d0, d1, false).score, m.score);
  // Seen from here the office is nearly symmetric: the proper match scores 0.9905, the mirror
  // image 1.0. A margin below that lead keeps the mirror image, one above it the proper match.
  const ShiftMatch plain = bestColumnShift(d0, d1, false);
  for (const auto& [margin, reversed] : {std::pair{0.005, true}, std::pair{0.02, false}}) {
    for (const ShiftMatch& r :
         {bestColumnShift(d0, d1, true, margin),
          bestColumnShiftCoarseToFine(d0, ShiftTables(d1), true, 3, margin)}) {
      EXPECT_EQ(r.reversed, reversed) << margin;
      EXPECT_EQ(r.score, reversed ? m.score : plain.score) << margin;
    }
  }
}

TEST(GeoContext, SimilaritiesInUnitIntervalAndOneForIdentical) {
  DescriptorConfig config;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 30.0f);
  std::bernoulli_distribution empty(0.1);
  for (int trial = 0; trial < 50; ++trial) {
    GeoContext a, b;
    for (int i = 0; i < config.num_bins; ++i) {
      a.range_m.push_back(empty(rng) ? 0.0f : u(rng));
      b.range_m.push_back(empty(rng) ? 0.0f : u(rng));
    }
    computeFeatures(a, config);
    computeFeatures(b, config);
    for (double s : {bestColumnShift(a, b, true).score, fftSimilarity(a, b), cvSimilarity(a, b),
                     inverseCosine(a.range_m.data(), b.range_m.data(), config.num_bins)}) {
      EXPECT_GE(s, 0.0);
      EXPECT_LE(s, 1.0);
    }
    EXPECT_NEAR(bestColumnShift(a, a, false).score, 1.0, 1e-6);
    EXPECT_EQ(bestColumnShift(a, a, false).shift, 0);
    EXPECT_NEAR(fftSimilarity(a, a), 1.0, 1e-9);
    EXPECT_NEAR(cvSimilarity(a, a), 1.0, 1e-12);
    const SimilarityWeights w;
    EXPECT_NEAR(combineSimilarity(1.0, 1.0, 1.0, w), 1.0, 1e-12);
    const double s = combineSimilarity(bestColumnShift(a, b, false).score, fftSimilarity(a, b),
                                       cvSimilarity(a, b), w);
    EXPECT_GE(s, 0.0);
    EXPECT_LE(s, 1.0);
  }
}

TEST(GeoContext, SimilaritiesAreScaleInvariant) {
  DescriptorConfig config;
  GeoContext a, b;
  for (int i = 0; i < config.num_bins; ++i) {
    a.range_m.push_back(5.0f + 3.0f * std::sin(0.3f * i));
    b.range_m.push_back(2.0f * a.range_m.back());
  }
  computeFeatures(a, config);
  computeFeatures(b, config);
  EXPECT_NEAR(bestColumnShift(a, b, false).score, 1.0, 1e-6);
  EXPECT_NEAR(fftSimilarity(a, b), 1.0, 1e-9);
  EXPECT_NEAR(cvSimilarity(a, b), 1.0, 1e-9);
}

TEST(GeoContext, ABinPartlyBeyondRangeHoldsTheRangeLimit) {
  // A pillar 10 m ahead covers a third of bin 0; the rest of the bin sees nothing within 30 m.
  // Cut at the range, the bin holds 30 m (what lies beyond is at least that far), not the
  // pillar; a bin the pillar fills holds the pillar either way.
  Points2d pts;
  for (double y = -0.12; y <= 0.12; y += 0.02) pts.emplace_back(10.0, y);
  for (double y = -1.0; y <= 1.0; y += 0.02)
    pts.emplace_back(10.0 * std::cos(0.5), 10.0 * std::sin(0.5) + y);
  DescriptorConfig config;
  config.point_radius_m = 0.02;
  config.clip_to_range = true;
  const GeoContext cut = computeGeoContext(pts, Vector2d::Zero(), config);
  config.clip_to_range = false;
  const GeoContext plain = computeGeoContext(pts, Vector2d::Zero(), config);
  const size_t full = static_cast<size_t>(std::lround(0.5 / (2.0 * M_PI / config.num_bins)));
  EXPECT_NEAR(plain.range_m[0], 10.0, 0.01);
  EXPECT_FLOAT_EQ(cut.range_m[0], 30.0f);
  EXPECT_NEAR(cut.range_m[full], plain.range_m[full], 1e-6);
  EXPECT_LT(cut.range_m[full], 10.5f);
  // Every other bin saw nothing: 30 m cut, empty plain.
  EXPECT_FLOAT_EQ(cut.range_m[45], 30.0f);
  EXPECT_FLOAT_EQ(plain.range_m[45], 0.0f);
}

TEST(GeoContext, AHoleInTheObservedWallsReadsTheFarthestSeenNotTheRange) {
  // Walls on a circle of 10 m with three 20 degree gaps. Through the gap at 0 deg the floor is
  // seen up to 9.8 m (a hole in the walls, not open space); through the gap at 90 deg a wall 35 m
  // away is seen (open beyond the 30 m range); through the gap at 180 deg nothing is seen.
  DescriptorConfig config;
  config.point_radius_m = 0.05;
  ASSERT_TRUE(config.clip_to_range);
  const double half_gap = 10.0 * M_PI / 180.0;
  const auto inGap = [&](double a) {
    for (double c : {0.0, 0.5 * M_PI, M_PI}) {
      if (std::abs(std::remainder(a - c, 2.0 * M_PI)) < half_gap) return true;
    }
    return false;
  };
  Points2d walls, beyond, floor;
  for (double a = -M_PI; a < M_PI; a += 0.002) {
    if (!inGap(a)) walls.emplace_back(10.0 * std::cos(a), 10.0 * std::sin(a));
  }
  for (double a = 0.5 * M_PI - half_gap; a < 0.5 * M_PI + half_gap; a += 0.002)
    beyond.emplace_back(35.0 * std::cos(a), 35.0 * std::sin(a));
  for (double a = -half_gap; a < half_gap; a += 0.002) {
    for (double r = 1.0; r <= 9.8 + 1e-9; r += 0.2)
      floor.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  const GeoContext obs =
      computeObservedGeoContext(walls, {&walls, &beyond, &floor}, Vector2d::Zero(), config);
  const GeoContext walls_only = computeGeoContext(walls, Vector2d::Zero(), config);
  const int quarter = config.num_bins / 4;
  EXPECT_NEAR(obs.range_m[0], 9.8, 0.05);
  EXPECT_FLOAT_EQ(walls_only.range_m[0], 30.0f);  // a hole read as open space
  EXPECT_FLOAT_EQ(obs.range_m[static_cast<size_t>(quarter)], 30.0f);
  EXPECT_FLOAT_EQ(obs.range_m[static_cast<size_t>(2 * quarter)], 0.0f);  // unknown
  EXPECT_FLOAT_EQ(walls_only.range_m[static_cast<size_t>(2 * quarter)], 30.0f);
  EXPECT_NEAR(obs.range_m[static_cast<size_t>(quarter / 2)], 10.0, 0.05);
  EXPECT_TRUE(obs.valid);
  // Without the cut the seen points change nothing.
  config.clip_to_range = false;
  EXPECT_EQ(
      computeObservedGeoContext(walls, {&walls, &beyond, &floor}, Vector2d::Zero(), config).range_m,
      computeGeoContext(walls, Vector2d::Zero(), config).range_m);
}

TEST(GeoContext, OnlyBinsInsideTheRangeMakeACutDescriptorValid) {
  // Cut at the range, a place with nothing within it has every bin at the limit: flat, and
  // describing nothing. It is invalid, like the plain descriptor of no points.
  DescriptorConfig config;
  config.min_valid_bins = 6;
  config.clip_to_range = true;
  Points2d pts;
  const double step = 2.0 * M_PI / config.num_bins;
  // An arc at 5 m over the whole of bin k.
  const auto arc = [&](int k) {
    for (double a = (k - 0.5) * step; a <= (k + 0.5) * step; a += 0.002)
      pts.emplace_back(5.0 * std::cos(a), 5.0 * std::sin(a));
  };
  for (int k = 0; k < 5; ++k) arc(k);
  // One point in each of many other bins: seen, but partly beyond range, so not inside it.
  for (int k = 20; k < 80; k += 3)
    pts.emplace_back(5.0 * std::cos(k * step), 5.0 * std::sin(k * step));
  EXPECT_FALSE(computeGeoContext(pts, Vector2d::Zero(), config).valid);
  arc(5);
  EXPECT_TRUE(computeGeoContext(pts, Vector2d::Zero(), config).valid);
  EXPECT_FALSE(computeGeoContext(Points2d{}, Vector2d::Zero(), config).valid);
}

TEST(GeoContext, EmptyOrSparseInputIsInvalid) {
  DescriptorConfig config;
  EXPECT_FALSE(computeGeoContext({}, Vector2d::Zero(), config).valid);
  EXPECT_FALSE(
      computeGeoContext({Vector2d(10, 10), Vector2d(20, 0)}, Vector2d::Zero(), config).valid);
  EXPECT_EQ(bestColumnShift(GeoContext{}, GeoContext{}, true).score, 0.0);
}

TEST(GeoContext, ConfigValidationNamesTheKey) {
  const auto expectErrorNaming = [](const DescriptorConfig& c, const std::string& key) {
    try {
      c.validate();
      ADD_FAILURE() << "expected ConfigError naming " << key;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  DescriptorConfig c;
  c.coarse_shift_factor = 4;  // does not divide 90
  expectErrorNaming(c, "coarse_shift_factor");
  c = DescriptorConfig{};
  c.num_fft = 0;
  EXPECT_THROW(c.validate(), ConfigError);
  c = DescriptorConfig{};
  c.level_shift_half_width = -1;
  expectErrorNaming(c, "level_shift_half_width");
}

}  // namespace
}  // namespace efs::registration
