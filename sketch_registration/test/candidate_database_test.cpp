// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Single-frame retrieval when the sketch and the observation see to different ranges: the
// sketch's range limit is in sketch metres, the observation's in world metres, and the true
// scale between them is unknown (within the scale tolerance).
#include <gtest/gtest.h>

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

/// Share of the robot's positions at which a candidate within 4 m (sketch) of the truth is among
/// the top 5 % of all candidates. The observation sees `observed_range_m` (world metres).
double topFiveShare(const syn::Scenario& sc, const DescriptorConfig& sketch_config,
                    double observed_range_m) {
  const CandidateDatabase db(sc.sketch_points_m, sc.candidates_m, sketch_config);
  DescriptorConfig observed_config;
  observed_config.max_range_m = observed_range_m;
  const size_t k = static_cast<size_t>(std::ceil(0.05 * static_cast<double>(db.validCount())));
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
  sketch_config.empty_observed_bins_unknown = true;
  const double unseen = topFiveShare(sc, sketch_config, 30.0);
  sketch_config.empty_observed_bins_unknown = false;
  const double no_wall = topFiveShare(sc, sketch_config, 30.0);
  EXPECT_GE(unseen, 0.7);
  EXPECT_LT(no_wall, unseen - 0.25);
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
  const DescriptorConfig sketch_config = sketchDescriptorConfig(config);
  EXPECT_DOUBLE_EQ(sketch_config.max_range_m, 75.0);
  const double derived = topFiveShare(sc, sketch_config, 30.0);
  DescriptorConfig at_guess = sketch_config;
  at_guess.max_range_m = 30.0;
  const double guessed = topFiveShare(sc, at_guess, 30.0);
  EXPECT_GE(derived, 0.9);
  EXPECT_LT(guessed, derived - 0.2);
}

}  // namespace
}  // namespace efs::registration
