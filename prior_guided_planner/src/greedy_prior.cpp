// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/greedy_prior.h"

#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "efs_common/config_check.h"
#include "prior_guided_planner/cost_matrix.h"

namespace efs::planner {

void GreedyPriorConfig::validate() const {
  requireInRange("greedy.sensor_range_m", sensor_range_m, 0.1, 1e4);
  requireInRange("greedy.observed_radius_m", observed_radius_m, 0.0, 1e3);
  requireInRange("greedy.length_offset_m", length_offset_m, 1e-3, 1e4);
}

std::vector<Eigen::Vector2d> unobservedPredictedFree(const GuidepointPrior& prior,
                                                     const Hypothesis& h,
                                                     const ObservationQuery& observation,
                                                     const GreedyPriorConfig& config) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(prior.predicted_free_sketch_m.size());
  for (const Eigen::Vector2d& s : prior.predicted_free_sketch_m) {
    const Eigen::Vector2d w = h.T_world_sketch * s;
    if (observation) {
      const ObservationLevel level = observation(w, config.observed_radius_m);
      const bool known = config.poorly_observed_is_unknown
                             ? level == ObservationLevel::kWellObserved
                             : level != ObservationLevel::kNone;
      if (known) continue;
    }
    out.push_back(w);
  }
  return out;
}

namespace {

// Buckets of samples on a square grid of the sensor range: a viewpoint's samples lie in its
// bucket and the eight around it.
class SampleGrid {
 public:
  SampleGrid(const std::vector<Eigen::Vector2d>& pts, double cell_m) : pts_(pts), cell_(cell_m) {
    for (size_t i = 0; i < pts.size(); ++i)
      buckets_[key(cellOf(pts[i].x()), cellOf(pts[i].y()))].push_back(i);
  }
  size_t countWithin(const Eigen::Vector2d& c, double r) const {
    size_t n = 0;
    const int64_t cx = cellOf(c.x()), cy = cellOf(c.y());
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = buckets_.find(key(cx + dx, cy + dy));
        if (it == buckets_.end()) continue;
        for (size_t i : it->second) n += (pts_[i] - c).squaredNorm() <= r * r;
      }
    return n;
  }

 private:
  int64_t cellOf(double v) const { return static_cast<int64_t>(std::floor(v / cell_)); }
  static uint64_t key(int64_t x, int64_t y) {
    return (static_cast<uint64_t>(x) << 32) ^ (static_cast<uint64_t>(y) & 0xffffffffULL);
  }
  const std::vector<Eigen::Vector2d>& pts_;
  double cell_;
  std::unordered_map<uint64_t, std::vector<size_t>> buckets_;
};

}  // namespace

GreedyPriorScores scoreGreedyPrior(const std::vector<PlanViewpoint>& vps,
                                   const std::vector<double>& robot_len,
                                   const std::vector<Eigen::Vector2d>& unobserved,
                                   double sample_area_m2, const GreedyPriorConfig& config) {
  GreedyPriorScores s;
  s.gain_m2.assign(vps.size(), 0.0);
  s.utility.assign(vps.size(), 0.0);
  const SampleGrid grid(unobserved, config.sensor_range_m);
  for (size_t i = 0; i < vps.size(); ++i) {
    s.gain_m2[i] =
        sample_area_m2 * grid.countWithin(vps[i].position_world_m.head<2>(), config.sensor_range_m);
    if (!(robot_len[i] < kUnreachable) || s.gain_m2[i] <= 0.0) continue;
    s.utility[i] = s.gain_m2[i] / (robot_len[i] + config.length_offset_m);
    const int b = s.best;
    if (b < 0 || s.utility[i] > s.utility[b] ||
        (s.utility[i] == s.utility[b] && robot_len[i] < robot_len[b]))
      s.best = static_cast<int>(i);
  }
  return s;
}

}  // namespace efs::planner
