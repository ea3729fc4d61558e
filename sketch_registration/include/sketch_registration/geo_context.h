// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// GeoContext (paper Sec. V-A): the maximum horizontal range of the visible boundary in each of
// N_b azimuth bins, and the three similarities between a prior descriptor I^p and an observation
// descriptor I^o:
//   S_cos  inverse-weighted cosine (w_i = 1 / (I^p_i + I^o_i)), maximised over column shifts;
//   S_FFT  (cos(f^p, f^o) + 1) / 2 over the magnitudes of the N_c lowest DFT components;
//   S_cv   1 - |CV^p - CV^o| / (CV^p + CV^o);
// combined as S = S_cos^a1 * S_FFT^a2 * S_cv^a3.
//
// Bin k is centred on azimuth k * 2pi / N_b, so that a column shift of n bins is a rotation of
// exactly n * 2pi / N_b, and a reversed descriptor (a mirror image) stays bin-aligned.
#pragma once

#include <vector>

#include "sketch_registration/hpr.h"
#include "sketch_registration/types.h"

namespace efs::registration {

struct DescriptorConfig {
  int num_bins = 90;          ///< N_b
  int fine_bins_per_bin = 8;  ///< HPR depth-buffer resolution = N_b * this
  int num_fft = 10;           ///< N_c
  double min_range_m = 0.2;
  double max_range_m = 30.0;  ///< in the frame of the points described
  double point_radius_m = 0.1;
  int min_valid_bins = 6;  ///< fewer non-empty bins: the descriptor is unusable
  /// Retrieval searches column shifts coarse-to-fine: all shifts of a descriptor max-pooled by
  /// this factor, then every fine shift around the best `coarse_shift_keep` coarse ones. 1 =
  /// exhaustive. Must divide num_bins.
  int coarse_shift_factor = 3;
  int coarse_shift_keep = 3;
  /// CandidateDatabase compares a candidate at several range levels. The level whose
  /// shift-invariant bound is highest gets the full coarse-to-fine search; the others, the same
  /// place cut at another range, search only the fine shifts within this many bins of the shift
  /// that level matched, in its orientation. On registration_bench (synthetic garage, 25 384
  /// candidates, 7 levels) the frame median went from 261 to 151 ms CPU, every frame registering
  /// as before (see sketch_registration/README.md for the paper-size worlds).
  int level_shift_half_width = 2;
  /// Every level gets the full search (level_shift_half_width unused).
  bool full_shift_search_every_level = false;
  /// With mirror-image matching, a candidate takes its mirror-image match only where that beats
  /// its proper one by this much (S_cos). A place symmetric about a line through the viewpoint (a
  /// garage aisle) matches both ways alike; left to the larger score, half its candidates came out
  /// mirrored, and a 160 s paper-garage flight found only mirror-image fits (status
  /// mirrored_sketch for a precise drawing).
  double mirror_score_margin = 0.02;
  /// Length of coarse_range_m (0: no coarse stage).
  int numCoarseBins() const { return coarse_shift_factor > 1 ? num_bins / coarse_shift_factor : 0; }
  /// An empty bin of the observed descriptor means "nothing seen there within range", not "no
  /// wall": S_cos then leaves the prior's bin out. (The sketch's range limit is in sketch metres,
  /// the observation's in world metres; at a true scale above the guess the sketch sees walls
  /// beyond the observation's range, which an empty observed bin would otherwise count against.)
  bool empty_observed_bins_unknown = true;
  /// A fine (depth-buffer) bin with no boundary within max_range_m counts as max_range_m: each
  /// bin holds the maximum of min(range, max_range_m) over its fine bins, the descriptor of the
  /// place as a sensor limited to max_range_m sees it. Without it a bin partly beyond range holds
  /// the nearest thing in it (a pillar at 24 m), while a sketch that sees 2.5x as far holds the
  /// wall behind it at 80 m: on the paper garage (true scale 1.64 x the guess) the observed
  /// bins with every fine bin seen agreed with the true candidate's in 335 of 471 cases, those
  /// partly beyond range in 66 of 652. A sketch descriptor computed so is cut at any shorter
  /// range r by min(range, r) (CandidateDatabase's range levels). Then no bin is empty and
  /// empty_observed_bins_unknown has nothing to act on; a descriptor is valid with
  /// min_valid_bins bins closer than max_range_m.
  /// On the observation side an empty fine bin is told apart from a hole in the observed walls
  /// by computeObservedGeoContext. Measured (eta 5 %, with sketch_point_radius_m 0.15): paper
  /// garage precise 12.5 -> 100 %, deformed 29.2 -> 95.8 %; small garage 100 / 100 % (was 100 /
  /// 100), simple cave 100 / 99.4 % (99.4 / 100), indoor 99.3 / 97.8 % (98.5 / 98.5).
  bool clip_to_range = true;

  void validate() const;
  HprConfig hprConfig() const;
};

/// GeoContext descriptor with its shift-invariant features.
struct GeoContext {
  std::vector<float> range_m;         ///< N_b maximum ranges, 0 for an empty bin
  std::vector<float> fft_magnitude;   ///< N_c magnitudes |DFT_k|, k = 0..N_c-1
  std::vector<float> coarse_range_m;  ///< max-pooled by coarse_shift_factor (bins centred alike)
  double cv = 0.0;                    ///< coefficient of variation sigma / mu
  int described_bins = 0;  ///< bins whose view ends inside the range limit (`valid` counts them)
  bool valid = false;      ///< enough non-empty bins to be compared
};

/// Descriptor of a point set seen from `viewpoint_m` (HPR is part of it).
GeoContext computeGeoContext(const Points2d& points_m, const Eigen::Vector2d& viewpoint_m,
                             const DescriptorConfig& config);
/// The observation's descriptor: the boundary is `walls_m`; `seen_m` is everything the local map
/// has seen in the band (wall columns beyond max_range_m and the other columns included). With
/// clip_to_range a fine bin with no wall within range reads the farthest point of `seen_m` in it,
/// at most max_range_m (free space is known to reach that far: max_range_m when a wall or the
/// floor is seen beyond range), and a fine bin with nothing seen in it is unknown (it does not
/// raise its bin). A hole in the observed walls (an unseen stretch, a cave wall whose columns are
/// passage) then reads about the wall's distance instead of max_range_m: on the small simple cave
/// (one flight, the local map's in-band points) 623 of 740 partly seen bins agreed with the true
/// place's within 3 m this way, 89 when an empty fine bin read max_range_m. Without
/// clip_to_range: computeGeoContext(walls_m).
GeoContext computeObservedGeoContext(const Points2d& walls_m,
                                     const std::vector<const Points2d*>& seen_m,
                                     const Eigen::Vector2d& viewpoint_m,
                                     const DescriptorConfig& config);
/// Descriptor from a filled depth buffer (Phase 1 reuses one buffer for all candidates).
GeoContext geoContextFromBuffer(const PolarDepthBuffer& buffer, const DescriptorConfig& config);
/// Fills fft_magnitude, coarse_range_m, cv and valid from range_m.
void computeFeatures(GeoContext& descriptor, const DescriptorConfig& config);

/// S_inv_cos of two equally long range vectors (no shift), in [0, 1]. `unknown_empty`: an empty
/// observed bin means "not seen" and leaves the bin out (see DescriptorConfig).
double inverseCosine(const float* prior, const float* observed, int n, bool unknown_empty = false);

struct ShiftMatch {
  double score = 0.0;     ///< S_cos = max over shifts of S_inv_cos
  int shift = 0;          ///< n of the best shift
  bool reversed = false;  ///< the best match is the mirror image (I^o read backwards)
  double yaw_rad = 0.0;   ///< rotation sketch -> world implied by the shift
};

/// A shift and orientation as one number (refineShifts' centres): reversed * num_bins + shift.
inline int shiftCode(const ShiftMatch& m, int num_bins) {
  return (m.reversed ? num_bins : 0) + m.shift;
}

/// Maximises S_inv_cos over all column shifts of `observed` (and, with `try_reversed`, of its
/// mirror image). For the plain case prior_i = observed_{i+n} and the sketch-to-world yaw is
/// n * 2pi / N_b; for the mirrored case prior_i = observed_{n-i} and the yaw (after the
/// reflection diag(1,-1)) is also n * 2pi / N_b.
ShiftMatch bestColumnShift(const GeoContext& prior, const GeoContext& observed, bool try_reversed,
                           double mirror_margin = 0.0);

/// A ring of bins laid out twice so that every column shift is a contiguous window: plain,
/// values_i = ring_{i mod N}; mirrored, values_i = ring_{-i mod N} (the window starting at m reads
/// ring_{n' - i} with n' = -m). With `empty_is_unknown` its empty bins are unseen and every
/// window leaves them out.
struct ShiftTable {
  ShiftTable() = default;
  ShiftTable(const std::vector<float>& ring, bool mirrored, bool empty_is_unknown);
  std::vector<float> values;
  /// Positions of unseen bins, ascending (empty unless empty_is_unknown).
  std::vector<int> unseen;
  /// For each window start, the index into `unseen` of the first position at or after it: a
  /// window visits only its own unseen bins (retrieval scores ~10^6 windows a frame).
  std::vector<int> first_unseen;
};

/// The observation descriptor, fine and coarse, plain and mirrored (ShiftTable): prepared once
/// per frame, used for every candidate.
struct ShiftTables {
  explicit ShiftTables(const GeoContext& observed, bool empty_is_unknown = false);
  int n = 0, n_coarse = 0;
  ShiftTable plain, reversed, coarse_plain, coarse_reversed;
};
/// Exhaustive over all N_b shifts (and mirrored shifts).
ShiftMatch bestColumnShift(const float* prior_range_m, const ShiftTables& tables, bool try_reversed,
                           double mirror_margin = 0.0);
/// Coarse-to-fine (see DescriptorConfig::coarse_shift_factor); exhaustive when the prior has no
/// coarse descriptor.
ShiftMatch bestColumnShiftCoarseToFine(const GeoContext& prior, const ShiftTables& tables,
                                       bool try_reversed, int keep, double mirror_margin = 0.0);
/// The best of the fine shifts within `half_width` bins of each centre, a centre coded as
/// orientation * N_b + shift (orientation 1: mirrored); see shiftCode.
ShiftMatch refineShifts(const GeoContext& prior, const ShiftTables& tables,
                        const std::vector<int>& centres, int half_width,
                        double mirror_margin = 0.0);

double fftSimilarity(const GeoContext& prior, const GeoContext& observed);
/// The same from the two descriptors' fft_magnitude.
double fftSimilarity(const std::vector<float>& prior, const std::vector<float>& observed);
double cvSimilarity(const GeoContext& prior, const GeoContext& observed);
/// The same from the two descriptors' cv.
double cvSimilarity(double prior_cv, double observed_cv);

struct SimilarityWeights {
  double alpha_cos = 0.4;  ///< alpha_1
  double alpha_fft = 0.4;  ///< alpha_2
  double alpha_cv = 0.2;   ///< alpha_3
  void validate() const;
};

/// One similarity's factor of the weighted product: max(0, s)^alpha.
double similarityFactor(double s, double alpha);
/// The weighted product: the factors of S_cos, S_fft and S_cv, multiplied in that order.
double combineSimilarity(double s_cos, double s_fft, double s_cv, const SimilarityWeights& w);

}  // namespace efs::registration
