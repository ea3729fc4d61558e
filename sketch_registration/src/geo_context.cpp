// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/geo_context.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "efs_common/config_check.h"

namespace efs::registration {

void DescriptorConfig::validate() const {
  requireInRange("num_bins", num_bins, 8, 1024);
  requireInRange("fine_bins_per_bin", fine_bins_per_bin, 1, 256);
  requireInRange("num_fft", num_fft, 1, num_bins / 2);
  requireInRange("min_range_m", min_range_m, 0.0, 1e6);
  requirePositive("max_range_m", max_range_m);
  requireThat(max_range_m > min_range_m, "max_range_m", "must be > min_range_m");
  requireInRange("point_radius_m", point_radius_m, 0.0, 100.0);
  requireInRange("min_valid_bins", min_valid_bins, 1, num_bins);
  requireInRange("coarse_shift_factor", coarse_shift_factor, 1, num_bins);
  requireThat(num_bins % coarse_shift_factor == 0, "coarse_shift_factor", "must divide num_bins");
  requireInRange("coarse_shift_keep", coarse_shift_keep, 1, num_bins);
  requireInRange("level_shift_half_width", level_shift_half_width, 0, num_bins / 2);
  requireInRange("mirror_score_margin", mirror_score_margin, 0.0, 1.0);
}

HprConfig DescriptorConfig::hprConfig() const {
  HprConfig h;
  h.num_fine_bins = num_bins * fine_bins_per_bin;
  h.min_range_m = min_range_m;
  h.max_range_m = max_range_m;
  h.point_radius_m = point_radius_m;
  h.angle_offset_rad = M_PI / num_bins;  // coarse bin k centred on k * 2pi / N_b
  return h;
}

void SimilarityWeights::validate() const {
  requireInRange("alpha_cos", alpha_cos, 0.0, 100.0);
  requireInRange("alpha_fft", alpha_fft, 0.0, 100.0);
  requireInRange("alpha_cv", alpha_cv, 0.0, 100.0);
  requireThat(alpha_cos + alpha_fft + alpha_cv > 0.0, "alpha_cos", "weights must not all be 0");
}

void computeFeatures(GeoContext& d, const DescriptorConfig& config) {
  const int n = static_cast<int>(d.range_m.size());
  int nonzero = 0;
  // Clipped, a bin at the range limit saw nothing: only bins inside it describe the place.
  const float limit = config.clip_to_range ? static_cast<float>(config.max_range_m) * (1.0f - 1e-6f)
                                           : std::numeric_limits<float>::infinity();
  double sum = 0.0, sum2 = 0.0;
  for (float r : d.range_m) {
    nonzero += r > 0.0f && r < limit;
    sum += r;
    sum2 += double(r) * r;
  }
  const double mean = n > 0 ? sum / n : 0.0;
  const double var = n > 0 ? std::max(0.0, sum2 / n - mean * mean) : 0.0;
  d.cv = mean > 0.0 ? std::sqrt(var) / mean : 0.0;
  d.described_bins = nonzero;
  d.valid = nonzero >= config.min_valid_bins && mean > 0.0;
  d.coarse_range_m.clear();
  const int f = config.coarse_shift_factor;
  if (config.numCoarseBins() > 0 && n % f == 0) {
    // Coarse bin j is centred on fine bin f*j, so a coarse shift c is the fine shift f*c.
    const int lo = -(f - 1) / 2;
    d.coarse_range_m.assign(static_cast<size_t>(n / f), 0.0f);
    for (int j = 0; j < n / f; ++j) {
      float m = 0.0f;
      for (int k = 0; k < f; ++k)
        m = std::max(m, d.range_m[static_cast<size_t>(((f * j + lo + k) % n + n) % n)]);
      d.coarse_range_m[static_cast<size_t>(j)] = m;
    }
  }
  // Low-frequency DFT magnitudes: shift-invariant, so they describe layout without heading. A
  // direct DFT of N_c components costs N_b * N_c, less than an FFT's setup for N_b = 90.
  d.fft_magnitude.assign(static_cast<size_t>(config.num_fft), 0.0f);
  // Twiddles cached per descriptor length (Phase 1 computes ~20k of these).
  thread_local std::vector<double> cos_table, sin_table;
  thread_local int table_n = 0, table_k = 0;
  if (table_n != n || table_k < config.num_fft) {
    table_n = n;
    table_k = config.num_fft;
    cos_table.resize(static_cast<size_t>(n) * table_k);
    sin_table.resize(cos_table.size());
    for (int k = 0; k < table_k; ++k) {
      for (int i = 0; i < n; ++i) {
        const double a = 2.0 * M_PI * k * i / n;
        cos_table[static_cast<size_t>(k) * n + i] = std::cos(a);
        sin_table[static_cast<size_t>(k) * n + i] = std::sin(a);
      }
    }
  }
  for (int k = 0; k < config.num_fft; ++k) {
    double re = 0.0, im = 0.0;
    const double* c = cos_table.data() + static_cast<size_t>(k) * n;
    const double* sn = sin_table.data() + static_cast<size_t>(k) * n;
    for (int i = 0; i < n; ++i) {
      re += d.range_m[static_cast<size_t>(i)] * c[i];
      im -= d.range_m[static_cast<size_t>(i)] * sn[i];
    }
    d.fft_magnitude[static_cast<size_t>(k)] = static_cast<float>(std::hypot(re, im));
  }
}

namespace {

/// The descriptor from per-fine-bin ranges (+inf: nothing there, which reads max_range_m with
/// clip_to_range and leaves the bin empty otherwise).
GeoContext geoContextFromFine(const float* fine, const DescriptorConfig& config) {
  GeoContext d;
  d.range_m.assign(static_cast<size_t>(config.num_bins), 0.0f);
  const int m = config.fine_bins_per_bin;
  // The buffer holds no point beyond max_range_m, so a finite depth needs no clipping.
  const float beyond = config.clip_to_range ? static_cast<float>(config.max_range_m) : 0.0f;
  for (int i = 0; i < config.num_bins; ++i) {
    float best = 0.0f;
    for (int k = i * m; k < (i + 1) * m; ++k) {
      const float z = fine[k];
      best = std::max(best, std::isfinite(z) ? z : beyond);
    }
    d.range_m[static_cast<size_t>(i)] = best;
  }
  computeFeatures(d, config);
  return d;
}

}  // namespace

GeoContext geoContextFromBuffer(const PolarDepthBuffer& buffer, const DescriptorConfig& config) {
  return geoContextFromFine(buffer.depths().data(), config);
}

GeoContext computeGeoContext(const Points2d& points_m, const Eigen::Vector2d& viewpoint_m,
                             const DescriptorConfig& config) {
  PolarDepthBuffer buffer(config.hprConfig());
  buffer.splatAll(points_m, viewpoint_m);
  return geoContextFromBuffer(buffer, config);
}

GeoContext computeObservedGeoContext(const Points2d& walls_m,
                                     const std::vector<const Points2d*>& seen_m,
                                     const Eigen::Vector2d& viewpoint_m,
                                     const DescriptorConfig& config) {
  PolarDepthBuffer buffer(config.hprConfig());
  buffer.splatAll(walls_m, viewpoint_m);
  if (!config.clip_to_range) return geoContextFromBuffer(buffer, config);
  // 0 = nothing seen in the fine bin: unknown, it does not raise its bin's maximum.
  std::vector<float> fine(buffer.depths().size(), 0.0f);
  const float limit = static_cast<float>(config.max_range_m);
  for (const Points2d* points : seen_m) {
    for (const Eigen::Vector2d& p : *points) {
      const Eigen::Vector2d d = p - viewpoint_m;
      const double r = d.norm();
      if (!(r >= config.min_range_m)) continue;
      float& f = fine[static_cast<size_t>(buffer.fineBin(d.x(), d.y()))];
      f = std::max(f, std::min(static_cast<float>(r), limit));
    }
  }
  for (size_t k = 0; k < fine.size(); ++k) {
    if (std::isfinite(buffer.depth(static_cast<int>(k))))
      fine[k] = buffer.depth(static_cast<int>(k));
  }
  return geoContextFromFine(fine.data(), config);
}

namespace {

/// With w_i = 1 / (a_i + b_i):  sum w a^2 - sum w b^2 = sum (a - b), and
/// sum w a^2 + sum w b^2 = sum (a + b) - 2 sum w a b. Hence, with N = sum w a b, A = sum a and
/// B = sum b: sum w a^2 = A - N and sum w b^2 = B - N. One division pass per shift suffices, and
/// A, B are shift-invariant.
inline double inverseCosineWithSums(const float* prior, const float* observed, int n,
                                    float sum_prior, float sum_observed) {
  using Arr = Eigen::Map<const Eigen::ArrayXf>;
  const Arr a(prior, n), b(observed, n);
  // Bins empty on both sides contribute nothing (tiny epsilon instead of a branch).
  const float num = (a * b / (a + b + 1e-20f)).sum();
  const double da = double(sum_prior) - num, db = double(sum_observed) - num;
  if (!(da > 0.0) || !(db > 0.0)) return num > 0.0f ? 1.0 : 0.0;
  return std::min(1.0, std::max(0.0, num / std::sqrt(da * db)));
}

inline float sumOf(const float* x, int n) { return Eigen::Map<const Eigen::ArrayXf>(x, n).sum(); }

/// S_inv_cos of `prior` against the window of a doubled observed table starting at `start`. An
/// empty observed bin contributes a_i to the prior's norm (w a^2 = a); where it means "not seen"
/// (`unseen`: the table's empty positions) the prior's bin is left out of that norm instead. The
/// few empty positions are subtracted rather than the window masked: a mask pass per shift made
/// retrieval 67-79 % slower, this 25-30 %.
inline double windowScore(const float* prior, float sum_prior, const ShiftTable& table, int start,
                          int n, float sum_observed) {
  const int end = start + n;
  for (size_t k = static_cast<size_t>(table.first_unseen[static_cast<size_t>(start)]);
       k < table.unseen.size() && table.unseen[k] < end; ++k) {
    sum_prior -= prior[table.unseen[k] - start];
  }
  return inverseCosineWithSums(prior, table.values.data() + start, n, sum_prior, sum_observed);
}

std::vector<int> emptyPositions(const std::vector<float>& table, bool wanted) {
  std::vector<int> out;
  if (!wanted) return out;
  for (size_t i = 0; i < table.size(); ++i) {
    if (!(table[i] > 0.0f)) out.push_back(static_cast<int>(i));
  }
  return out;
}

/// first[s]: the index in `positions` (ascending) of the first position >= s, s = 0..size.
std::vector<int> firstAtOrAfter(const std::vector<int>& positions, size_t size) {
  std::vector<int> first(size + 1);
  size_t k = 0;
  for (size_t s = 0; s <= size; ++s) {
    while (k < positions.size() && positions[k] < static_cast<int>(s)) ++k;
    first[s] = static_cast<int>(k);
  }
  return first;
}

/// m mod n in [0, n) for n > 0, whatever the sign of m.
inline int wrapShift(int m, int n) { return (m % n + n) % n; }

}  // namespace

double inverseCosine(const float* prior, const float* observed, int n, bool unknown_empty) {
  float sum_prior = 0.0f;
  for (int i = 0; i < n; ++i) sum_prior += !unknown_empty || observed[i] > 0.0f ? prior[i] : 0.0f;
  return inverseCosineWithSums(prior, observed, n, sum_prior, sumOf(observed, n));
}

ShiftTable::ShiftTable(const std::vector<float>& ring, bool mirrored, bool empty_is_unknown) {
  const size_t n = ring.size();
  values.resize(2 * n);
  for (size_t i = 0; i < 2 * n; ++i) values[i] = ring[mirrored ? (2 * n - i) % n : i % n];
  unseen = emptyPositions(values, empty_is_unknown);
  first_unseen = firstAtOrAfter(unseen, values.size());
}

ShiftTables::ShiftTables(const GeoContext& observed, bool empty_is_unknown)
    : n(static_cast<int>(observed.range_m.size())),
      n_coarse(static_cast<int>(observed.coarse_range_m.size())),
      plain(observed.range_m, false, empty_is_unknown),
      reversed(observed.range_m, true, empty_is_unknown),
      coarse_plain(observed.coarse_range_m, false, empty_is_unknown),
      coarse_reversed(observed.coarse_range_m, true, empty_is_unknown) {}

namespace {
/// The mirror-image match only where it beats the proper one by `mirror_margin`: a place
/// symmetric about a line through the viewpoint matches both ways alike, and which one wins by
/// a hair is noise; a drawing is rarely mirrored, and a mirrored one beats its proper match by far.
ShiftMatch preferProper(const ShiftMatch& plain, const ShiftMatch& mirrored, double mirror_margin) {
  return mirrored.score > plain.score + mirror_margin ? mirrored : plain;
}
}  // namespace

ShiftMatch refineShifts(const GeoContext& prior, const ShiftTables& tables,
                        const std::vector<int>& centres, int half_width, double mirror_margin) {
  const int n = tables.n;
  ShiftMatch best_plain, best_mirrored;
  if (n == 0 || static_cast<int>(prior.range_m.size()) != n) return best_plain;
  const float sa = sumOf(prior.range_m.data(), n), sb = sumOf(tables.plain.values.data(), n);
  for (int centre : centres) {
    const bool rev = centre >= n;
    ShiftMatch& best = rev ? best_mirrored : best_plain;
    // Shifts step by one from the first: a wrap by comparison, not an integer division a window.
    int shift = wrapShift(wrapShift(centre, n) - half_width, n);
    for (int d = -half_width; d <= half_width; ++d, shift = shift + 1 == n ? 0 : shift + 1) {
      // Plain: window at `shift`; mirrored: shift n' is the window at -n'.
      const double v = rev ? windowScore(prior.range_m.data(), sa, tables.reversed,
                                         shift == 0 ? 0 : n - shift, n, sb)
                           : windowScore(prior.range_m.data(), sa, tables.plain, shift, n, sb);
      if (v > best.score) best = ShiftMatch{v, shift, rev, 0.0};
    }
  }
  ShiftMatch best = preferProper(best_plain, best_mirrored, mirror_margin);
  best.yaw_rad = std::remainder(2.0 * M_PI * best.shift / n, 2.0 * M_PI);
  return best;
}

namespace {

/// Coarse stage: the `keep` best coarse shifts, best first, as fine centres (shiftCode).
void bestCoarseCentres(const GeoContext& prior, const ShiftTables& tables, bool try_reversed,
                       int keep, std::vector<int>& centres) {
  centres.clear();
  const int n = tables.n, nc = tables.n_coarse;
  const float sca = sumOf(prior.coarse_range_m.data(), nc);
  const float scb = sumOf(tables.coarse_plain.values.data(), nc);
  thread_local std::vector<std::pair<float, int>> coarse;  // (score, orientation * nc + shift)
  coarse.clear();
  for (int c = 0; c < nc; ++c) {
    coarse.emplace_back(static_cast<float>(windowScore(prior.coarse_range_m.data(), sca,
                                                       tables.coarse_plain, c, nc, scb)),
                        c);
  }
  if (try_reversed) {
    for (int m = 0; m < nc; ++m) {
      coarse.emplace_back(static_cast<float>(windowScore(prior.coarse_range_m.data(), sca,
                                                         tables.coarse_reversed, m, nc, scb)),
                          nc + (nc - m) % nc);
    }
  }
  keep = std::min<int>(keep, static_cast<int>(coarse.size()));
  // The keep best, best first. Where the keep + 1 best scores are distinct (nearly always) they
  // are found in one pass; with a tie among them, partial_sort decides, as it always has (which
  // of equal scores comes first is its heap's doing, and the fine stage follows that order).
  constexpr int kMaxTracked = 8;
  std::pair<float, int> best[kMaxTracked];
  int tracked = 0;
  const int wanted = std::min(keep + 1, static_cast<int>(coarse.size()));
  bool distinct = wanted <= kMaxTracked;
  if (distinct) {
    for (const auto& entry : coarse) {
      if (tracked == wanted && !(entry.first > best[tracked - 1].first)) continue;
      int q = tracked < wanted ? tracked++ : tracked - 1;
      for (; q > 0 && best[q - 1].first < entry.first; --q) best[q] = best[q - 1];
      best[q] = entry;
    }
    for (int q = 0; q + 1 < tracked; ++q) distinct = distinct && best[q].first > best[q + 1].first;
  }
  if (!distinct) {
    std::partial_sort(coarse.begin(), coarse.begin() + keep, coarse.end(),
                      [](const auto& a, const auto& b) { return a.first > b.first; });
  }
  // Coarse bin j is centred on fine bin f * j, so a coarse shift c is the fine shift f * c.
  const int f = n / nc;
  for (int q = 0; q < keep; ++q) {
    const int code = distinct ? best[q].second : coarse[static_cast<size_t>(q)].second;
    centres.push_back((code >= nc ? n : 0) + f * (code % nc));
  }
}

}  // namespace

ShiftMatch bestColumnShiftCoarseToFine(const GeoContext& prior, const ShiftTables& tables,
                                       bool try_reversed, int keep, double mirror_margin) {
  const int n = tables.n, nc = tables.n_coarse;
  if (nc == 0 || static_cast<int>(prior.coarse_range_m.size()) != nc || n % nc != 0) {
    return bestColumnShift(prior.range_m.data(), tables, try_reversed, mirror_margin);
  }
  thread_local std::vector<int> centres;
  bestCoarseCentres(prior, tables, try_reversed, keep, centres);
  // Every fine shift within a coarse bin of each kept coarse shift.
  return refineShifts(prior, tables, centres, n / nc - 1, mirror_margin);
}

ShiftMatch bestColumnShift(const float* prior, const ShiftTables& tables, bool try_reversed,
                           double mirror_margin) {
  ShiftMatch plain, mirrored;
  const int n = tables.n;
  if (n == 0) return plain;
  const float sa = sumOf(prior, n), sb = sumOf(tables.plain.values.data(), n);
  for (int s = 0; s < n; ++s) {
    const double v = windowScore(prior, sa, tables.plain, s, n, sb);
    if (v > plain.score) plain = ShiftMatch{v, s, false, 0.0};
  }
  if (try_reversed) {
    for (int m = 0; m < n; ++m) {
      const double v = windowScore(prior, sa, tables.reversed, m, n, sb);
      if (v > mirrored.score) mirrored = ShiftMatch{v, (n - m) % n, true, 0.0};
    }
  }
  ShiftMatch best = preferProper(plain, mirrored, mirror_margin);
  best.yaw_rad = std::remainder(2.0 * M_PI * best.shift / n, 2.0 * M_PI);
  return best;
}

ShiftMatch bestColumnShift(const GeoContext& prior, const GeoContext& observed, bool try_reversed,
                           double mirror_margin) {
  if (prior.range_m.empty() || prior.range_m.size() != observed.range_m.size()) return {};
  return bestColumnShift(prior.range_m.data(), ShiftTables(observed), try_reversed, mirror_margin);
}

double fftSimilarity(const std::vector<float>& prior, const std::vector<float>& observed) {
  const size_t n = std::min(prior.size(), observed.size());
  double dot = 0.0, na = 0.0, nb = 0.0;
  for (size_t k = 0; k < n; ++k) {
    dot += double(prior[k]) * observed[k];
    na += double(prior[k]) * prior[k];
    nb += double(observed[k]) * observed[k];
  }
  if (!(na > 0.0) || !(nb > 0.0)) return 0.0;
  return std::min(1.0, std::max(0.0, 0.5 * (dot / std::sqrt(na * nb) + 1.0)));
}

double fftSimilarity(const GeoContext& prior, const GeoContext& observed) {
  return fftSimilarity(prior.fft_magnitude, observed.fft_magnitude);
}

double cvSimilarity(double prior_cv, double observed_cv) {
  const double sum = prior_cv + observed_cv;
  if (!(sum > 0.0)) return 1.0;  // both perfectly uniform
  return std::min(1.0, std::max(0.0, 1.0 - std::abs(prior_cv - observed_cv) / sum));
}

double cvSimilarity(const GeoContext& prior, const GeoContext& observed) {
  return cvSimilarity(prior.cv, observed.cv);
}

double similarityFactor(double s, double alpha) { return std::pow(std::max(0.0, s), alpha); }

double combineSimilarity(double s_cos, double s_fft, double s_cv, const SimilarityWeights& w) {
  return similarityFactor(s_cos, w.alpha_cos) * similarityFactor(s_fft, w.alpha_fft) *
         similarityFactor(s_cv, w.alpha_cv);
}

}  // namespace efs::registration
