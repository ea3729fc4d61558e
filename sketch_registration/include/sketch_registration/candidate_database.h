// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Phase 1 of Algorithm 1 (descriptor precomputation over the candidate locations of the sketch)
// and the single-frame retrieval FindCand (rank all candidates by the combined similarity, keep
// the top eta, spatially downsample).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "sketch_registration/geo_context.h"
#include "sketch_registration/types.h"

namespace efs::registration {

/// Candidate locations on a `d_gap_m` grid over [min_m, max_m] wherever `traversable` says so.
/// (The prior bundle normally provides them; this keeps the module usable without it.)
Points2d makeCandidateGrid(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m,
                           double d_gap_m,
                           const std::function<bool(const Eigen::Vector2d&)>& traversable);

struct RetrievalConfig {
  double eta = 0.05;                   ///< candidate rate: top fraction kept (paper eta)
  /// At least this many are ranked however small the sketch: eta of a 40 m cave's 101
  /// candidates is 6, 2-3 after downsampling, and the truth was often not among them (seen: a
  /// recorded cave flight never registered). No effect once eta N is larger (the paper's worlds).
  int min_ranked_candidates = 12;
  SimilarityWeights weights;           ///< alpha_1..3
  double downsample_radius_m = 3.0;    ///< sketch frame; raw candidates closer merge
  int max_candidates_per_frame = 120;  ///< bounds the triplet combinatorics
  bool try_reversed = true;            ///< also match the mirror image (mirrored sketches)
  void validate() const;
};

/// One retrieved candidate: a sketch location that may be where the robot is.
struct Candidate {
  int index = -1;  ///< into the database
  Eigen::Vector2d c_sketch = Eigen::Vector2d::Zero();
  double score = 0.0;  ///< combined S
  double s_cos = 0.0, s_fft = 0.0, s_cv = 0.0;
  double yaw_rad = 0.0;    ///< sketch -> world rotation from the best column shift
  bool reflected = false;  ///< best match was the mirror image
};

class CandidateDatabase {
 public:
  CandidateDatabase() = default;
  /// Phase 1: HPR + GeoContext at every location. `config.max_range_m` is in sketch metres.
  CandidateDatabase(const Points2d& sketch_points_m, Points2d candidates_m,
                    const DescriptorConfig& config);

  size_t size() const { return locations_.size(); }
  size_t validCount() const { return valid_count_; }
  const Points2d& locations() const { return locations_; }
  const GeoContext& descriptor(size_t i) const { return descriptors_[i]; }
  const DescriptorConfig& config() const { return config_; }

  /// The `k` best candidates by combined similarity, best first (exact: the cheap shift-invariant
  /// factors bound the score, so the costly shift search runs only where it can matter).
  std::vector<Candidate> rank(const GeoContext& observed, size_t k, const SimilarityWeights& w,
                              bool try_reversed) const;
  /// Scores every candidate (evaluation and ablations; slow on purpose).
  std::vector<Candidate> scoreAll(const GeoContext& observed, const SimilarityWeights& w,
                                  bool try_reversed) const;
  /// FindCand: top eta ranked, then greedy spatial downsampling (best kept first).
  std::vector<Candidate> findCandidates(const GeoContext& observed,
                                        const RetrievalConfig& config) const;

 private:
  Candidate score(size_t i, const GeoContext& observed, const ShiftTables& tables,
                  const SimilarityWeights& w, bool try_reversed) const;
  DescriptorConfig config_;
  Points2d locations_;
  std::vector<GeoContext> descriptors_;
  size_t valid_count_ = 0;
};

}  // namespace efs::registration
