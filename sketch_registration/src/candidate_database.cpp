// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/candidate_database.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>
#include <unordered_map>

#include "efs_common/config_check.h"

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

}  // namespace

CandidateDatabase::CandidateDatabase(const Points2d& sketch_points_m, Points2d candidates_m,
                                     const DescriptorConfig& config)
    : config_(config) {
  config_.validate();
  Points2d finite_points;
  finite_points.reserve(sketch_points_m.size());
  for (const auto& p : sketch_points_m) {
    if (p.allFinite()) finite_points.push_back(p);
  }
  for (const auto& c : candidates_m) {
    if (c.allFinite()) locations_.push_back(c);
  }
  descriptors_.resize(locations_.size());
  if (finite_points.empty()) {
    for (auto& d : descriptors_) d.range_m.assign(static_cast<size_t>(config_.num_bins), 0.0f);
    return;
  }
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
    descriptors_[j] = geoContextFromBuffer(buffer, config_);
    valid_count_ += descriptors_[j].valid;
  }
}

Candidate CandidateDatabase::score(size_t i, const GeoContext& observed, const ShiftTables& tables,
                                   const SimilarityWeights& w, bool try_reversed) const {
  Candidate c;
  c.index = static_cast<int>(i);
  c.c_sketch = locations_[i];
  const GeoContext& d = descriptors_[i];
  if (!d.valid || !observed.valid) return c;
  const ShiftMatch m =
      bestColumnShiftCoarseToFine(d, tables, try_reversed, config_.coarse_shift_keep);
  c.s_cos = m.score;
  c.s_fft = fftSimilarity(d, observed);
  c.s_cv = cvSimilarity(d, observed);
  c.score = combineSimilarity(c.s_cos, c.s_fft, c.s_cv, w);
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
  out.reserve(size());
  for (size_t i = 0; i < size(); ++i) out.push_back(score(i, observed, tables, w, try_reversed));
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
  // Upper bound of S with S_cos <= 1; visit in decreasing bound, stop once the bound cannot beat
  // the k-th best exact score.
  std::vector<std::pair<double, int>> bound;
  bound.reserve(size());
  for (size_t i = 0; i < size(); ++i) {
    const GeoContext& d = descriptors_[i];
    if (!d.valid) continue;
    bound.emplace_back(
        combineSimilarity(1.0, fftSimilarity(d, observed), cvSimilarity(d, observed), w),
        static_cast<int>(i));
  }
  std::sort(bound.begin(), bound.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
  const ShiftTables tables(observed, config_.empty_observed_bins_unknown);
  auto worse = [](const Candidate& a, const Candidate& b) { return a.score > b.score; };
  std::priority_queue<Candidate, std::vector<Candidate>, decltype(worse)> heap(worse);
  for (const auto& [ub, i] : bound) {
    if (heap.size() >= k && ub <= heap.top().score) break;
    Candidate c = score(static_cast<size_t>(i), observed, tables, w, try_reversed);
    if (heap.size() < k) {
      heap.push(c);
    } else if (c.score > heap.top().score) {
      heap.pop();
      heap.push(c);
    }
  }
  out.reserve(heap.size());
  while (!heap.empty()) {
    out.push_back(heap.top());
    heap.pop();
  }
  std::reverse(out.begin(), out.end());
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
  auto key = [&](long long ix, long long iy) { return (ix << 32) ^ (iy & 0xffffffffLL); };
  for (const Candidate& c : raw) {
    if (static_cast<int>(out.size()) >= config.max_candidates_per_frame) break;
    if (r > 0.0) {
      const long long ix = static_cast<long long>(std::floor(c.c_sketch.x() / r));
      const long long iy = static_cast<long long>(std::floor(c.c_sketch.y() / r));
      bool suppressed = false;
      for (long long dy = -1; dy <= 1 && !suppressed; ++dy) {
        for (long long dx = -1; dx <= 1 && !suppressed; ++dx) {
          auto it = cells.find(key(ix + dx, iy + dy));
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
      cells[key(ix, iy)].push_back(static_cast<int>(out.size()));
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace efs::registration
