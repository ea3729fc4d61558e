// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/candidate_database.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>

#include "efs_common/config_check.h"
#include "efs_common/voxel_key.h"

namespace efs::registration {

Points2d makeCandidateGrid(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m,
                           double d_gap_m,
                           const std::function<bool(const Eigen::Vector2d&)>& traversable) {
  requirePositive("d_gap_m", d_gap_m);
  Points2d out;
  if (!min_m.allFinite() || !max_m.allFinite()) return out;
  for (double y = min_m.y(); y <= max_m.y() + 1e-9; y += d_gap_m) {
    for (double x = min_m.x(); x <= max_m.x() + 1e-9; x += d_gap_m) {
      const Eigen::Vector2d p(x, y);
      if (traversable(p)) out.push_back(p);
    }
  }
  return out;
}

void RetrievalConfig::validate() const {
  requireInRange("eta", eta, 1e-6, 1.0);
  requireInRange("min_ranked_candidates", min_ranked_candidates, 0, 100000);
  weights.validate();
  requireInRange("downsample_radius_m", downsample_radius_m, 0.0, 1e4);
  requireInRange("max_candidates_per_frame", max_candidates_per_frame, 1, 100000);
}

namespace {

/// Uniform bucket grid over the sketch points: Phase 1 visits only the cells within range.
struct BucketGrid {
  double cell_m = 2.0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  int nx = 0, ny = 0;
  std::vector<int> start;  // CSR layout: cell c holds points [start[c], start[c+1])
  std::vector<Eigen::Vector2f> pts;

  BucketGrid(const Points2d& points, double cell) : cell_m(cell) {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
    for (const auto& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    if (points.empty()) return;
    origin = lo;
    nx = static_cast<int>((hi.x() - lo.x()) / cell_m) + 1;
    ny = static_cast<int>((hi.y() - lo.y()) / cell_m) + 1;
    std::vector<int> count(static_cast<size_t>(nx) * ny + 1, 0);
    std::vector<int> cell_of(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      cell_of[i] = cellIndex(points[i]);
      ++count[static_cast<size_t>(cell_of[i]) + 1];
    }
    start.assign(count.size(), 0);
    std::partial_sum(count.begin(), count.end(), start.begin());
    std::vector<int> fill(start.begin(), start.end() - 1);
    pts.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      pts[static_cast<size_t>(fill[static_cast<size_t>(cell_of[i])]++)] = points[i].cast<float>();
    }
  }
  int cellIndex(const Eigen::Vector2d& p) const {
    const int ix = std::min(nx - 1, std::max(0, static_cast<int>((p.x() - origin.x()) / cell_m)));
    const int iy = std::min(ny - 1, std::max(0, static_cast<int>((p.y() - origin.y()) / cell_m)));
    return iy * nx + ix;
  }
};

/// Orders `bounds`, given in increasing pair, by decreasing value and, on ties, increasing pair.
/// A least-significant-digit radix sort on the values' bits, stable, so ties keep their pairs'
/// order: the comparison sort's order, in a few linear passes over the ~180 000 pairs of
/// registration_bench's garage instead of ~18 comparisons each. Non-negative doubles order as
/// their bit patterns; any other value (none is expected: bounds are products of similarities in
/// [0, 1]) falls back to the comparison sort.
template <typename Bound>
void sortByDecreasingValue(std::vector<Bound>& bounds, std::vector<Bound>& scratch) {
  const auto byValue = [](const Bound& a, const Bound& b) {
    return a.value > b.value || (a.value == b.value && a.pair < b.pair);
  };
  const bool radix_safe = std::all_of(bounds.begin(), bounds.end(), [](const Bound& b) {
    return b.value >= 0.0 && b.value <= std::numeric_limits<double>::max();
  });
  if (!radix_safe) {
    std::sort(bounds.begin(), bounds.end(), byValue);
    return;
  }
  // Descending value is ascending complemented bits; -0.0 is 0.0.
  const auto key = [](const Bound& b) {
    uint64_t bits = 0;
    if (b.value != 0.0) std::memcpy(&bits, &b.value, sizeof bits);
    return ~bits;
  };
  constexpr int kDigitBits = 11;
  constexpr size_t kBuckets = size_t{1} << kDigitBits;
  constexpr int kPasses = (64 + kDigitBits - 1) / kDigitBits;
  std::vector<size_t> counts(kPasses * kBuckets, 0);
  for (const Bound& b : bounds) {
    const uint64_t k = key(b);
    for (int pass = 0; pass < kPasses; ++pass)
      ++counts[pass * kBuckets + ((k >> (pass * kDigitBits)) & (kBuckets - 1))];
  }
  scratch.resize(bounds.size());
  for (int pass = 0; pass < kPasses; ++pass) {
    size_t* count = counts.data() + pass * kBuckets;
    // A digit every value shares moves nothing.
    if (std::any_of(count, count + kBuckets, [&](size_t c) { return c == bounds.size(); }))
      continue;
    size_t offset = 0;
    for (size_t d = 0; d < kBuckets; ++d) offset += std::exchange(count[d], offset);
    for (const Bound& b : bounds)
      scratch[count[(key(b) >> (pass * kDigitBits)) & (kBuckets - 1)]++] = b;
    bounds.swap(scratch);
  }
}

}  // namespace

CandidateDatabase::CandidateDatabase(const Points2d& sketch_points_m, Points2d candidates_m,
                                     const DescriptorConfig& config,
                                     std::vector<double> range_levels_m)
    : config_(config), levels_m_(std::move(range_levels_m)) {
  config_.validate();
  // Unclipped, a bin's maximum over fine bins cannot be cut at a shorter range afterwards.
  if (levels_m_.empty() || !config_.clip_to_range) levels_m_ = {config_.max_range_m};
  for (double r : levels_m_) {
    requireThat(r > config_.min_range_m && r <= config_.max_range_m, "range_levels_m",
                "each must be in (min_range_m, max_range_m]");
  }
  std::sort(levels_m_.begin(), levels_m_.end(), std::greater<double>());
  Points2d finite_points;
  finite_points.reserve(sketch_points_m.size());
  for (const auto& p : sketch_points_m) {
    if (p.allFinite()) finite_points.push_back(p);
  }
  for (const auto& c : candidates_m) {
    if (c.allFinite()) locations_.push_back(c);
  }
  n_fine_ = static_cast<size_t>(config_.num_bins);
  n_coarse_ = static_cast<size_t>(config_.numCoarseBins());
  stride_ = n_fine_ + n_coarse_;
  ranges_.assign(locations_.size() * stride_, 0.0f);
  if (!finite_points.empty()) {
    const double cell = std::max(1.0, config_.max_range_m / 8.0);
    const BucketGrid grid(finite_points, cell);
    PolarDepthBuffer buffer(config_.hprConfig());
    const int reach = static_cast<int>(std::ceil(config_.max_range_m / cell));
    for (size_t j = 0; j < locations_.size(); ++j) {
      buffer.reset();
      const Eigen::Vector2d& c = locations_[j];
      const int cx = static_cast<int>(std::floor((c.x() - grid.origin.x()) / cell));
      const int cy = static_cast<int>(std::floor((c.y() - grid.origin.y()) / cell));
      for (int iy = std::max(0, cy - reach); iy <= std::min(grid.ny - 1, cy + reach); ++iy) {
        for (int ix = std::max(0, cx - reach); ix <= std::min(grid.nx - 1, cx + reach); ++ix) {
          const int cidx = iy * grid.nx + ix;
          for (int k = grid.start[static_cast<size_t>(cidx)];
               k < grid.start[static_cast<size_t>(cidx) + 1]; ++k) {
            const Eigen::Vector2f& p = grid.pts[static_cast<size_t>(k)];
            buffer.splat(p.x() - c.x(), p.y() - c.y());
          }
        }
      }
      const GeoContext d = geoContextFromBuffer(buffer, config_);
      float* to = ranges_.data() + j * stride_;
      std::copy(d.range_m.begin(), d.range_m.end(), to);
      std::copy(d.coarse_range_m.begin(), d.coarse_range_m.end(), to + n_fine_);
    }
  }
  // The shift-invariant features of every level, so that retrieval can bound each (candidate,
  // level) before the costly shift search.
  level_features_.resize(locations_.size() * levels_m_.size());
  for (size_t j = 0; j < locations_.size(); ++j) {
    bool any = false;
    for (int l = 0; l < static_cast<int>(levels_m_.size()); ++l) {
      GeoContext d = descriptorAtLevel(j, l);
      LevelFeatures& f = level_features_[j * levels_m_.size() + static_cast<size_t>(l)];
      f.fft_magnitude = std::move(d.fft_magnitude);
      f.cv = d.cv;
      f.valid = d.valid;
      any |= d.valid;
    }
    valid_count_ += any;
  }
}

/// The descriptor cut at range r: min(range, r) per bin. The maximum over a bin's fine bins
/// commutes with the cut, so the coarse (max-pooled) descriptor is cut alike.
void CandidateDatabase::cutAt(size_t i, int l, GeoContext& out) const {
  const float r = static_cast<float>(levels_m_[static_cast<size_t>(l)]);
  const auto cut = [r](const float* in, size_t n, std::vector<float>& to) {
    to.resize(n);
    std::transform(in, in + n, to.begin(), [r](float x) { return std::min(x, r); });
  };
  cut(ranges(i), n_fine_, out.range_m);
  cut(ranges(i) + n_fine_, n_coarse_, out.coarse_range_m);
}

GeoContext CandidateDatabase::descriptorAtLevel(size_t i, int l) const {
  GeoContext d;
  cutAt(i, l, d);
  DescriptorConfig c = config_;
  c.max_range_m = levels_m_[static_cast<size_t>(l)];
  computeFeatures(d, c);
  return d;
}

Candidate CandidateDatabase::unscored(size_t i, int l) const {
  Candidate c;
  c.index = static_cast<int>(i);
  c.c_sketch = locations_[i];
  c.range_level = l;
  return c;
}

double CandidateDatabase::Invariants::combined(double s_cos, const SimilarityWeights& w) const {
  return combinedFromFactor(similarityFactor(s_cos, w.alpha_cos));
}

CandidateDatabase::Invariants CandidateDatabase::invariants(size_t i, int l,
                                                            const GeoContext& observed,
                                                            const SimilarityWeights& w) const {
  const LevelFeatures& f = level(i, l);
  Invariants inv;
  inv.s_fft = fftSimilarity(f.fft_magnitude, observed.fft_magnitude);
  inv.s_cv = cvSimilarity(f.cv, observed.cv);
  inv.fft_factor = similarityFactor(inv.s_fft, w.alpha_fft);
  inv.cv_factor = similarityFactor(inv.s_cv, w.alpha_cv);
  return inv;
}

Candidate CandidateDatabase::score(size_t i, int l, const Invariants& inv,
                                   const ShiftTables& tables, const SimilarityWeights& w,
                                   bool try_reversed, GeoContext& scratch, int* shift_code,
                                   bool later_level) const {
  Candidate c = unscored(i, l);
  if (tables.n == 0) return c;
  cutAt(i, l, scratch);
  ShiftMatch m;
  if (later_level && shift_code != nullptr && !config_.full_shift_search_every_level) {
    thread_local std::vector<int> centre(1);
    centre[0] = *shift_code;
    m = refineShifts(scratch, tables, centre, config_.level_shift_half_width,
                     config_.mirror_score_margin);
  } else {
    m = bestColumnShiftCoarseToFine(scratch, tables, try_reversed, config_.coarse_shift_keep,
                                    config_.mirror_score_margin);
    if (shift_code != nullptr) *shift_code = shiftCode(m, tables.n);
  }
  c.s_cos = m.score;
  c.s_fft = inv.s_fft;
  c.s_cv = inv.s_cv;
  c.score = inv.combined(c.s_cos, w);
  c.yaw_rad = m.yaw_rad;
  c.reflected = m.reversed;
  return c;
}

std::vector<Candidate> CandidateDatabase::scoreAll(const GeoContext& observed,
                                                   const SimilarityWeights& w,
                                                   bool try_reversed) const {
  std::vector<Candidate> out;
  if (!observed.valid || observed.range_m.size() != static_cast<size_t>(config_.num_bins)) {
    return out;
  }
  const ShiftTables tables(observed, config_.empty_observed_bins_unknown);
  GeoContext scratch;
  out.reserve(size());
  const int nl = static_cast<int>(levels_m_.size());
  std::vector<Invariants> inv(static_cast<size_t>(nl));
  for (size_t i = 0; i < size(); ++i) {
    // The level rank() scores first: the highest bound, the lowest level on ties.
    std::optional<int> first;
    for (int l = 0; l < nl; ++l) {
      if (!level(i, l).valid) continue;
      inv[static_cast<size_t>(l)] = invariants(i, l, observed, w);
      if (!first || inv[static_cast<size_t>(l)].combined(1.0, w) >
                        inv[static_cast<size_t>(*first)].combined(1.0, w)) {
        first = l;
      }
    }
    if (!first) {
      out.push_back(unscored(i, 0));
      continue;
    }
    int code = 0;
    Candidate best = score(i, *first, inv[static_cast<size_t>(*first)], tables, w, try_reversed,
                           scratch, &code, false);
    for (int l = 0; l < nl; ++l) {
      if (l == *first || !level(i, l).valid) continue;
      const Candidate c =
          score(i, l, inv[static_cast<size_t>(l)], tables, w, try_reversed, scratch, &code, true);
      if (c.score > best.score) best = c;
    }
    out.push_back(best);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  return out;
}

std::vector<Candidate> CandidateDatabase::rank(const GeoContext& observed, size_t k,
                                               const SimilarityWeights& w,
                                               bool try_reversed) const {
  std::vector<Candidate> out;
  if (k == 0 || !observed.valid ||
      observed.range_m.size() != static_cast<size_t>(config_.num_bins)) {
    return out;
  }
  // Upper bound of S with S_cos <= 1 for every (candidate, level); visit in decreasing bound, stop
  // once the bound cannot beat the k-th best candidate's exact score (its best level). A pair is
  // i * levels + l, so ties visit candidates, then levels, in order.
  const size_t nl = levels_m_.size();
  // Each entry of the kept arrays (RankBuffers) read is written first this frame: inv where its
  // pair is valid, best and first_shift where their candidate is scored.
  std::vector<PairBound>& bounds = rank_buffers_.bounds;
  std::vector<Invariants>& inv = rank_buffers_.inv;
  bounds.clear();
  bounds.reserve(size() * nl);
  inv.resize(size() * nl);
  const double cos_factor_at_one = similarityFactor(1.0, w.alpha_cos);
  for (size_t i = 0; i < size(); ++i) {
    for (int l = 0; l < static_cast<int>(nl); ++l) {
      if (!level(i, l).valid) continue;
      const size_t pair = i * nl + static_cast<size_t>(l);
      inv[pair] = invariants(i, l, observed, w);
      bounds.push_back({inv[pair].combinedFromFactor(cos_factor_at_one), pair});
    }
  }
  sortByDecreasingValue(bounds, rank_buffers_.sort_scratch);
  const ShiftTables tables(observed, config_.empty_observed_bins_unknown);
  GeoContext scratch;
  std::vector<Candidate>& best = rank_buffers_.best;
  best.resize(size());
  // best[i].score where candidate i is scored (scores lie in [0, 1]; -inf: not scored yet, below
  // any bound): the loop reads it for every pair visited, in bound order (candidates at random),
  // so it is kept dense.
  constexpr double kNotScored = -std::numeric_limits<double>::infinity();
  std::vector<double>& best_score = rank_buffers_.best_score;
  best_score.assign(size(), kNotScored);
  std::set<std::pair<double, int>> top;  // the k best (score, index), ascending
  // The shift code of each candidate's first scored level (its highest bound): the others
  // search near it (DescriptorConfig::level_shift_half_width).
  std::vector<int>& first_shift = rank_buffers_.first_shift;
  first_shift.resize(size());
  // The pairs come in bound order, not memory order: what the pair kPrefetch ahead reads is
  // fetched while this one is scored.
  constexpr size_t kPrefetch = 4;
  const size_t line_floats = 64 / sizeof(float);
  for (size_t j = 0; j < bounds.size(); ++j) {
    const PairBound& b = bounds[j];
    if (top.size() >= k && b.value <= top.begin()->first) break;
    if (j + kPrefetch < bounds.size()) {
      const size_t ahead = bounds[j + kPrefetch].pair;
      __builtin_prefetch(&inv[ahead]);
      __builtin_prefetch(&best_score[ahead / nl]);
      const float* r = ranges(ahead / nl);
      for (size_t f = 0; f < stride_; f += line_floats) __builtin_prefetch(r + f);
    }
    const size_t i = b.pair / nl;
    const bool scored = best_score[i] > kNotScored;
    // Another level of a candidate already scored only matters if it may beat that score.
    if (scored && b.value <= best_score[i]) continue;
    const int l = static_cast<int>(b.pair % nl);
    const Candidate c =
        score(i, l, inv[b.pair], tables, w, try_reversed, scratch, &first_shift[i], scored);
    if (scored) {
      if (!(c.score > best_score[i])) continue;
      top.erase({best_score[i], static_cast<int>(i)});  // absent when it was trimmed: no-op
    }
    best[i] = c;
    best_score[i] = c.score;
    // Below the k-th best it would be trimmed at once (most scored pairs are): the set, a node
    // allocation and two rebalancings each, is left alone.
    const std::pair<double, int> entry(c.score, static_cast<int>(i));
    if (top.size() >= k && entry < *top.begin()) continue;
    top.insert(entry);
    if (top.size() > k) top.erase(top.begin());
  }
  out.reserve(top.size());
  for (auto it = top.rbegin(); it != top.rend(); ++it) {
    out.push_back(best[static_cast<size_t>(it->second)]);
  }
  std::stable_sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) {
    return a.score > b.score || (a.score == b.score && a.index < b.index);
  });
  return out;
}

std::vector<Candidate> CandidateDatabase::findCandidates(const GeoContext& observed,
                                                         const RetrievalConfig& config) const {
  const size_t k =
      std::max(static_cast<size_t>(std::ceil(config.eta * static_cast<double>(valid_count_))),
               std::min(static_cast<size_t>(config.min_ranked_candidates), valid_count_));
  const std::vector<Candidate> raw =
      rank(observed, std::max<size_t>(k, 1), config.weights, config.try_reversed);
  std::vector<Candidate> out;
  const double r = config.downsample_radius_m;
  const double r2 = r * r;
  // Greedy non-maximum suppression on a hash grid of cell r.
  std::unordered_map<long long, std::vector<int>> cells;
  for (const Candidate& c : raw) {
    if (static_cast<int>(out.size()) >= config.max_candidates_per_frame) break;
    if (r > 0.0) {
      const long long ix = static_cast<long long>(std::floor(c.c_sketch.x() / r));
      const long long iy = static_cast<long long>(std::floor(c.c_sketch.y() / r));
      bool suppressed = false;
      for (long long dy = -1; dy <= 1 && !suppressed; ++dy) {
        for (long long dx = -1; dx <= 1 && !suppressed; ++dx) {
          auto it = cells.find(cellKey2d(ix + dx, iy + dy));
          if (it == cells.end()) continue;
          for (int o : it->second) {
            if ((out[static_cast<size_t>(o)].c_sketch - c.c_sketch).squaredNorm() < r2) {
              suppressed = true;
              break;
            }
          }
        }
      }
      if (suppressed) continue;
      cells[cellKey2d(ix, iy)].push_back(static_cast<int>(out.size()));
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace efs::registration
