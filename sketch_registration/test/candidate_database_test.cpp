// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Single-frame retrieval when the sketch and the observation see to different ranges: the
// sketch's range limit is in sketch metres, the observation's in world metres, and the true
// scale between them is unknown (within the scale tolerance).
#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <vector>

#include "sketch_registration/candidate_database.h"
#include "sketch_registration/sketch_registration.h"
#include "sketch_registration/synthetic_scene.h"

namespace efs::registration {
namespace {

using Eigen::Vector2d;
namespace syn = synthetic;

/// A hall like the small generated garage (40 x 34 sketch metres): open floor, three pillars, a
/// partition wall and a service core, so that most of what distinguishes places is far away.
syn::Scenario hallAt(const Sim2& T) {
  syn::FloorPlan plan;
  std::vector<syn::Box> solids;
  const Vector2d lo(0.0, 0.0), hi(40.0, 34.0);
  syn::addBox(plan, lo, hi);
  for (const Vector2d& c : {Vector2d(6.5, 11.5), Vector2d(14.0, 11.5), Vector2d(21.5, 11.5)}) {
    solids.push_back({c - Vector2d(0.3, 0.3), c + Vector2d(0.3, 0.3)});
  }
  solids.push_back({Vector2d(30.0, 7.0), Vector2d(32.5, 16.0)});
  for (const syn::Box& b : solids) syn::addBox(plan, b.min_m, b.max_m);
  plan.push_back({Vector2d(20.0, 6.8), Vector2d(20.0, 16.2)});
  const Points2d waypoints = {{3, 3}, {37, 3}, {37, 20}, {3, 20}, {3, 31}, {37, 31}};
  return syn::makeScenario(plan, solids, lo, hi, T, waypoints, 0.1, 1.0, 4.0);
}

/// A parking deck (60 x 48 sketch metres): pillars every 8 m, two partitions and a core. From
/// most places the outer walls lie beyond the observation's 30 m at scale 1.6 while pillars lie
/// within it, in bins whose other directions reach the walls (the paper garage).
syn::Scenario deckAt(const Sim2& T) {
  syn::FloorPlan plan;
  std::vector<syn::Box> solids;
  const Vector2d lo(0.0, 0.0), hi(60.0, 48.0);
  syn::addBox(plan, lo, hi);
  for (double x = 8.0; x < 60.0; x += 8.0) {
    for (double y = 8.0; y < 48.0; y += 8.0) {
      solids.push_back({Vector2d(x - 0.3, y - 0.3), Vector2d(x + 0.3, y + 0.3)});
    }
  }
  solids.push_back({Vector2d(44.0, 30.0), Vector2d(50.0, 38.0)});
  for (const syn::Box& b : solids) syn::addBox(plan, b.min_m, b.max_m);
  plan.push_back({Vector2d(12.0, 20.0), Vector2d(28.0, 20.0)});
  plan.push_back({Vector2d(36.0, 4.0), Vector2d(36.0, 14.0)});
  const Points2d waypoints = {{4, 4}, {56, 4}, {56, 24}, {4, 24}, {4, 44}, {56, 44}};
  return syn::makeScenario(plan, solids, lo, hi, T, waypoints, 0.1, 1.0, 4.0);
}

/// The observation's descriptor config: it sees `range_m` (world metres), cut there or not.
DescriptorConfig observedConfig(double range_m, bool clip_to_range) {
  DescriptorConfig c;
  c.max_range_m = range_m;
  c.clip_to_range = clip_to_range;
  return c;
}

/// eta = 5 % of the database's valid candidates, as retrieval ranks them.
size_t topFivePercent(const CandidateDatabase& db) {
  return static_cast<size_t>(std::ceil(0.05 * static_cast<double>(db.validCount())));
}

/// Share of the robot's positions at which a candidate within 4 m (sketch) of the truth is among
/// the top 5 % of all candidates. The observation sees `observed_range_m` (world metres), cut
/// at it (clip_to_range) as the sketch is; `range_levels_m` go to the database.
double topFiveShare(const syn::Scenario& sc, const DescriptorConfig& sketch_config,
                    double observed_range_m, std::vector<double> range_levels_m = {}) {
  const CandidateDatabase db(sc.sketch_points_m, sc.candidates_m, sketch_config,
                             std::move(range_levels_m));
  const DescriptorConfig observed_config =
      observedConfig(observed_range_m, sketch_config.clip_to_range);
  const size_t k = topFivePercent(db);
  int hits = 0, frames = 0;
  for (const Vector2d& p : sc.path_world_m) {
    const Points2d seen = syn::castRays(sc.world_plan, p, 1440, observed_range_m);
    const GeoContext observed = computeGeoContext(seen, p, observed_config);
    if (!observed.valid) continue;
    ++frames;
    const Vector2d truth = sc.T_world_sketch.inverse().apply(p);
    for (const Candidate& c : db.rank(observed, k, SimilarityWeights{}, false)) {
      if ((c.c_sketch - truth).norm() <= 4.0) {
        ++hits;
        break;
      }
    }
  }
  EXPECT_GE(frames, 20);
  return frames > 0 ? static_cast<double>(hits) / frames : 0.0;
}

TEST(Retrieval, EmptyObservedBinsCountAsUnseen) {
  // Drawn at 1.6 world metres per sketch metre: much of the 64 x 54 m world lies beyond the
  // observation's 30 m, while the sketch (75 sketch metres = 120 m) sees all of it. Counted as
  // "no wall", the empty bins rank the truth low (the failure of the garage, README).
  const syn::Scenario sc = hallAt(Sim2(0.7, 1.6, Vector2d(12.0, -5.0)));
  DescriptorConfig sketch_config;
  sketch_config.max_range_m = 75.0;
  sketch_config.clip_to_range = false;  // empty bins exist only uncut
  sketch_config.empty_observed_bins_unknown = true;
  const double unseen = topFiveShare(sc, sketch_config, 30.0);
  sketch_config.empty_observed_bins_unknown = false;
  const double no_wall = topFiveShare(sc, sketch_config, 30.0);
  EXPECT_GE(unseen, 0.7);
  EXPECT_LT(no_wall, unseen - 0.25);
}

TEST(Retrieval, SketchCutAtTheObservationsRangeFindsTheDeck) {
  // Drawn at 1.6 world metres per sketch metre, guessed 1: the sketch sees 75 sketch metres
  // (120 m) where the observation sees 30 m. Bins where the observation holds a pillar and the
  // sketch the wall behind it ranked the truth low; cut at the range level nearest the true
  // scale, both describe the same 30 m.
  const syn::Scenario sc = deckAt(Sim2(0.7, 1.6, Vector2d(12.0, -5.0)));
  SketchRegistrationConfig config;  // scale_guess 1, tolerance 2.5, 7 scale levels
  config.descriptor.clip_to_range = true;
  DescriptorConfig sketch_config = sketchDescriptorConfig(config);
  const double levels = topFiveShare(sc, sketch_config, 30.0, sketchRangeLevelsM(config));
  const double one_level = topFiveShare(sc, sketch_config, 30.0);
  sketch_config.clip_to_range = false;
  const double legacy = topFiveShare(sc, sketch_config, 30.0);
  EXPECT_GE(levels, 0.9);
  EXPECT_GT(levels, one_level + 0.1);
  EXPECT_GT(levels, legacy + 0.1);
}

TEST(Retrieval, RankIsTheTopOfTheExhaustiveScoring) {
  // rank() skips the shift search wherever the shift-invariant factors bound the score below
  // what is already held (the k-th best, or the candidate's own best level): it must return
  // exactly the k best that scoring every candidate at every level gives, mirror images too.
  const syn::Scenario sc = deckAt(Sim2(0.7, 1.6, Vector2d(12.0, -5.0)));
  SketchRegistrationConfig config;
  config.descriptor.clip_to_range = true;
  const CandidateDatabase db(sc.sketch_points_m, sc.candidates_m, sketchDescriptorConfig(config),
                             sketchRangeLevelsM(config));
  ASSERT_GT(db.rangeLevelsM().size(), 1u);
  const DescriptorConfig observed_config = observedConfig(30.0, true);
  const size_t k = topFivePercent(db);
  int compared = 0;
  for (size_t f = 0; f < sc.path_world_m.size(); f += 7) {
    const Vector2d p = sc.path_world_m[f];
    const GeoContext observed =
        computeGeoContext(syn::castRays(sc.world_plan, p, 1440, 30.0), p, observed_config);
    if (!observed.valid) continue;
    for (const bool mirrored : {false, true}) {
      const std::vector<Candidate> ranked = db.rank(observed, k, SimilarityWeights{}, mirrored);
      const std::vector<Candidate> all = db.scoreAll(observed, SimilarityWeights{}, mirrored);
      ASSERT_EQ(ranked.size(), k);
      for (size_t j = 0; j < k; ++j) {
        EXPECT_EQ(ranked[j].index, all[j].index) << "frame " << f << ", place " << j;
        EXPECT_DOUBLE_EQ(ranked[j].score, all[j].score) << "frame " << f << ", place " << j;
      }
      ++compared;
    }
  }
  EXPECT_GE(compared, 6);
}

TEST(Retrieval, LevelsAfterTheFirstSearchedNearItsShiftRankAsTheFullSearch) {
  // A candidate's levels are one place cut at several ranges: searching the others only near the
  // shift its first level matched must find the true place as often as searching each level in
  // full, and keep nearly the same top 5 %.
  const syn::Scenario sc = deckAt(Sim2(0.7, 1.6, Vector2d(12.0, -5.0)));
  SketchRegistrationConfig config;
  config.descriptor.clip_to_range = true;
  DescriptorConfig near_config = sketchDescriptorConfig(config);
  ASSERT_FALSE(near_config.full_shift_search_every_level);
  DescriptorConfig full_config = near_config;
  full_config.full_shift_search_every_level = true;
  const double near_share = topFiveShare(sc, near_config, 30.0, sketchRangeLevelsM(config));
  const double full_share = topFiveShare(sc, full_config, 30.0, sketchRangeLevelsM(config));
  EXPECT_GE(near_share, 0.9);
  EXPECT_GE(near_share, full_share - 0.02);

  const CandidateDatabase near_db(sc.sketch_points_m, sc.candidates_m, near_config,
                                  sketchRangeLevelsM(config));
  const CandidateDatabase full_db(sc.sketch_points_m, sc.candidates_m, full_config,
                                  sketchRangeLevelsM(config));
  const size_t k = topFivePercent(near_db);
  size_t shared = 0, total = 0;
  for (size_t f = 0; f < sc.path_world_m.size(); f += 5) {
    const Vector2d p = sc.path_world_m[f];
    const GeoContext observed = computeGeoContext(syn::castRays(sc.world_plan, p, 1440, 30.0), p,
                                                  observedConfig(30.0, true));
    if (!observed.valid) continue;
    const std::vector<Candidate> a = near_db.rank(observed, k, SimilarityWeights{}, true);
    const std::vector<Candidate> b = full_db.rank(observed, k, SimilarityWeights{}, true);
    for (const Candidate& c : a) {
      shared +=
          std::any_of(b.begin(), b.end(), [&c](const Candidate& o) { return o.index == c.index; });
    }
    total += a.size();
  }
  ASSERT_GT(total, 0u);
  // Measured: both 97.5 % of the positions; 99.95 % of the top 5 % shared.
  EXPECT_GE(static_cast<double>(shared) / static_cast<double>(total), 0.98);
}

TEST(Retrieval, RangeLevelsSpanTheScaleTolerance) {
  SketchRegistrationConfig config;
  config.scale_guess = 2.0;
  config.scale_levels = 5;
  const std::vector<double> levels = sketchRangeLevelsM(config);
  ASSERT_EQ(levels.size(), 5u);
  // R / s for s from s_g / f to s_g f: 30 / 0.8 down to 30 / 5, geometric.
  EXPECT_NEAR(levels.front(), 37.5, 1e-9);
  EXPECT_NEAR(levels.front(), sketchDescriptorConfig(config).max_range_m, 1e-9);
  EXPECT_NEAR(levels[2], 15.0, 1e-9);
  EXPECT_NEAR(levels.back(), 6.0, 1e-9);
  EXPECT_NEAR(levels[1] / levels[2], levels[3] / levels[4], 1e-9);
  config.scale_levels = 1;
  EXPECT_EQ(sketchRangeLevelsM(config), std::vector<double>{15.0});
}

TEST(Retrieval, ALevelIsTheDescriptorComputedAtThatRange) {
  // Cutting the stored descriptor at r (min(range, r)) must equal describing the sketch with a
  // range limit r: retrieval relies on it instead of storing a descriptor per level.
  const syn::Scenario sc = deckAt(Sim2());
  DescriptorConfig config;
  config.max_range_m = 75.0;
  config.clip_to_range = true;
  const std::vector<double> levels = {75.0, 40.0, 22.5, 12.0};
  Points2d locations;
  for (size_t i = 0; i < sc.candidates_m.size(); i += 97) locations.push_back(sc.candidates_m[i]);
  const CandidateDatabase db(sc.sketch_points_m, locations, config, levels);
  ASSERT_EQ(db.rangeLevelsM(), levels);
  for (size_t i = 0; i < db.size(); ++i) {
    for (int l = 0; l < static_cast<int>(levels.size()); ++l) {
      DescriptorConfig at = config;
      at.max_range_m = levels[static_cast<size_t>(l)];
      const GeoContext direct = computeGeoContext(sc.sketch_points_m, db.locations()[i], at);
      const GeoContext cut = db.descriptorAtLevel(i, l);
      ASSERT_EQ(cut.range_m.size(), direct.range_m.size());
      for (size_t b = 0; b < cut.range_m.size(); ++b) {
        EXPECT_NEAR(cut.range_m[b], direct.range_m[b], 1e-4) << "candidate " << i << " level " << l;
      }
      EXPECT_NEAR(cut.cv, direct.cv, 1e-6);
      EXPECT_EQ(cut.valid, direct.valid);
    }
  }
}

TEST(Retrieval, MaskedCosineIgnoresOnlyTheUnseenBins) {
  // The observation is the prior cut at a range: masked, the unseen bins do not count.
  GeoContext prior, observed;
  DescriptorConfig config;
  for (int i = 0; i < config.num_bins; ++i) {
    const float r = 10.0f + 25.0f * std::abs(std::sin(0.07f * i));
    prior.range_m.push_back(r);
    observed.range_m.push_back(r <= 30.0f ? r : 0.0f);
  }
  const int n = config.num_bins;
  EXPECT_NEAR(inverseCosine(prior.range_m.data(), observed.range_m.data(), n, true), 1.0, 1e-6);
  EXPECT_LT(inverseCosine(prior.range_m.data(), observed.range_m.data(), n, false), 0.9);
  // A wall seen where the prior has none still counts against the match.
  prior.range_m[3] = 0.0f;
  EXPECT_LT(inverseCosine(prior.range_m.data(), observed.range_m.data(), n, true), 0.99);
  computeFeatures(prior, config);
  computeFeatures(observed, config);
  EXPECT_NEAR(bestColumnShiftCoarseToFine(prior, ShiftTables(observed, true), false, 3).score,
              inverseCosine(prior.range_m.data(), observed.range_m.data(), n, true), 1e-6);
}

TEST(Retrieval, SketchSeesAsFarAsTheObservationAtTheSmallestScale) {
  // Drawn larger than guessed (0.6 world metres per sketch metre): at the guessed scale the
  // sketch's 30 m would be 18 world metres, and the walls the observation sees at 18-30 m in the
  // 24 x 20 m world would be missing from the sketch's descriptor.
  const syn::Scenario sc = hallAt(Sim2(0.7, 0.6, Vector2d(12.0, -5.0)));
  SketchRegistrationConfig config;  // scale_guess 1, tolerance 2.5, descriptor range 30 m
  DescriptorConfig cut = sketchDescriptorConfig(config);
  EXPECT_DOUBLE_EQ(cut.max_range_m, 75.0);
  // Cut at the range levels (the default), one of which lies near 30 / 0.6 = 50 sketch metres.
  ASSERT_TRUE(cut.clip_to_range);
  EXPECT_GE(topFiveShare(sc, cut, 30.0, sketchRangeLevelsM(config)), 0.9);
  // Not cut (empty observed bins unseen), the sketch must see at least as far as the
  // observation, hence its 75 sketch metres.
  DescriptorConfig sketch_config = cut;
  sketch_config.clip_to_range = false;
  const double derived = topFiveShare(sc, sketch_config, 30.0);
  DescriptorConfig at_guess = sketch_config;
  at_guess.max_range_m = 30.0;
  const double guessed = topFiveShare(sc, at_guess, 30.0);
  EXPECT_GE(derived, 0.9);
  EXPECT_LT(guessed, derived - 0.2);
}

}  // namespace
}  // namespace efs::registration
