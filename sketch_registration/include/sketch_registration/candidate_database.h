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
  double eta = 0.05;  ///< candidate rate: top fraction kept (paper eta)
  /// At least this many are ranked however small the sketch: eta of a 40 m cave's 101
  /// candidates is 6, 2-3 after downsampling, and the truth was often not among them (seen: a
  /// recorded cave flight never registered). No effect once eta N is larger (the paper's worlds).
  int min_ranked_candidates = 12;
  SimilarityWeights weights;         ///< alpha_1..3
  double downsample_radius_m = 3.0;  ///< sketch frame; raw candidates closer merge
  /// Bounds the triplet combinatorics. The paper has no such bound. At 120 the scaled paper
  /// garage (39 429 candidates, its 1 m grid nearly a world metre) lost the true place in 13 of
  /// 58 frames: more than 120 distinct places among its repeated bays ranked above it (77.6 %
  /// single-frame at eta 5 %; 94.8 % at 1000, frame median 159 -> 232 ms; the precise garage's
  /// 84 -> 95 ms).
  int max_candidates_per_frame = 1000;
  bool try_reversed = true;  ///< also match the mirror image (mirrored sketches)
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
  int range_level = 0;     ///< index of the best range level (CandidateDatabase)
};

class CandidateDatabase {
 public:
  CandidateDatabase() = default;
  /// Phase 1: HPR + GeoContext at every location. `config.max_range_m` is in sketch metres.
  /// `range_levels_m` (sketch metres, each in (min_range_m, max_range_m]): with
  /// config.clip_to_range, the ranges at which the observation's range limit may lie, one per
  /// admissible scale; a candidate is compared with its descriptor cut at each (min(range, r)),
  /// and its best level counts. Empty: max_range_m alone.
  CandidateDatabase(const Points2d& sketch_points_m, Points2d candidates_m,
                    const DescriptorConfig& config, std::vector<double> range_levels_m = {});

  size_t size() const { return locations_.size(); }
  size_t validCount() const { return valid_count_; }
  const Points2d& locations() const { return locations_; }
  /// Candidate i's descriptor cut at range level `level` (with its features).
  GeoContext descriptorAtLevel(size_t i, int level) const;
  const std::vector<double>& rangeLevelsM() const { return levels_m_; }
  const DescriptorConfig& config() const { return config_; }

  /// The `k` best candidates by combined similarity, best first: the top k of scoreAll (the cheap
  /// shift-invariant factors bound the score, so the costly shift search runs only where it can
  /// matter). A candidate's levels after its first are searched near that level's shift
  /// (DescriptorConfig::level_shift_half_width).
  std::vector<Candidate> rank(const GeoContext& observed, size_t k, const SimilarityWeights& w,
                              bool try_reversed) const;
  /// Scores every candidate (evaluation and ablations; slow on purpose).
  std::vector<Candidate> scoreAll(const GeoContext& observed, const SimilarityWeights& w,
                                  bool try_reversed) const;
  /// FindCand: top eta ranked, then greedy spatial downsampling (best kept first).
  std::vector<Candidate> findCandidates(const GeoContext& observed,
                                        const RetrievalConfig& config) const;

 private:
  /// Shift-invariant features of candidate i at one range level (Phase 1).
  struct LevelFeatures {
    std::vector<float> fft_magnitude;
    double cv = 0.0;
    bool valid = false;
  };
  const LevelFeatures& level(size_t i, int l) const {
    return level_features_[i * levels_m_.size() + static_cast<size_t>(l)];
  }
  /// The shift-invariant factors of S for candidate i at level l: computed once per frame, they
  /// bound the score (with S_cos <= 1) and complete it after the shift search. Their powers are
  /// kept so that a scored pair raises only S_cos to its weight.
  struct Invariants {
    double s_fft = 0.0, s_cv = 0.0;
    double fft_factor = 0.0, cv_factor = 0.0;  ///< s_fft^alpha_fft, s_cv^alpha_cv
    /// combineSimilarity(s_cos, s_fft, s_cv, w), multiplied in its order (the same bits).
    double combined(double s_cos, const SimilarityWeights& w) const;
    /// The same from S_cos's factor, similarityFactor(s_cos, alpha_cos): the bound's factor at
    /// S_cos = 1 is taken once a frame (pow(1, alpha) costs a whole pow, ~180 000 a frame).
    double combinedFromFactor(double cos_factor) const {
      return cos_factor * fft_factor * cv_factor;
    }
  };
  Invariants invariants(size_t i, int l, const GeoContext& observed,
                        const SimilarityWeights& w) const;
  /// Candidate i at level l with no similarity (an unusable descriptor).
  Candidate unscored(size_t i, int l) const;
  /// Candidate i at level l, which must be valid, by the shift search. A `later_level` of the
  /// candidate (not its first) searches only within level_shift_half_width of *shift_code
  /// (shiftCode), unless full_shift_search_every_level; a full search writes its best shift's
  /// code to *shift_code when that is given.
  Candidate score(size_t i, int l, const Invariants& inv, const ShiftTables& tables,
                  const SimilarityWeights& w, bool try_reversed, GeoContext& scratch,
                  int* shift_code = nullptr, bool later_level = false) const;
  /// Candidate i's descriptor cut at level l: range_m and coarse_range_m only.
  void cutAt(size_t i, int l, GeoContext& out) const;
  /// A (candidate, level) pair, i * levels + l, and its bound on the score.
  struct PairBound {
    double value;
    size_t pair;
  };
  /// rank()'s per-frame arrays (~10 MB on registration_bench's garage), kept from frame to frame
  /// rather than allocated, faulted in and zeroed afresh; rank() writes each entry it reads in
  /// the same frame. Hence rank() is not for concurrent calls on one database (a registration
  /// owns its own).
  struct RankBuffers {
    std::vector<PairBound> bounds, sort_scratch;
    std::vector<Invariants> inv;
    std::vector<Candidate> best;
    std::vector<double> best_score;
    std::vector<int> first_shift;
  };
  mutable RankBuffers rank_buffers_;
  const float* ranges(size_t i) const { return ranges_.data() + i * stride_; }
  DescriptorConfig config_;
  Points2d locations_;
  /// Every candidate's descriptor at max_range_m: num_bins ranges, then the coarse ones, `stride_`
  /// floats a candidate in one block, so that retrieval, which visits candidates out of order,
  /// can prefetch what it scores next.
  std::vector<float> ranges_;
  size_t n_fine_ = 0, n_coarse_ = 0, stride_ = 0;
  std::vector<double> levels_m_;               ///< descending; levels_m_[0] may equal max_range_m
  std::vector<LevelFeatures> level_features_;  ///< candidate-major
  size_t valid_count_ = 0;                     ///< candidates valid at some level
};

}  // namespace efs::registration
