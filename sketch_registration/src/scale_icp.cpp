// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/scale_icp.h"

#include <algorithm>
#include <cmath>

#include "efs_common/angles.h"
#include "efs_common/config_check.h"
#include "sketch_registration/hpr.h"
#include "sketch_registration/sim2_fit.h"

namespace efs::registration {

void ScaleIcpConfig::validate() const {
  requireInRange("max_iterations", max_iterations, 1, 10000);
  requirePositive("max_correspondence_m", max_correspondence_m);
  requirePositive("min_correspondence_m", min_correspondence_m);
  requireThat(min_correspondence_m <= max_correspondence_m, "min_correspondence_m",
              "must be <= max_correspondence_m");
  requireInRange("anneal_factor", anneal_factor, 0.01, 1.0);
  requireInRange("trim_ratio", trim_ratio, 0.05, 1.0);
  requirePositive("scale_min", scale_min);
  requireThat(scale_max >= scale_min, "scale_max", "must be >= scale_min");
  requireInRange("max_scale_step", max_scale_step, 0.0, 10.0);
  requirePositive("convergence_m", convergence_m);
  requireInRange("fitness_trim_ratio", fitness_trim_ratio, 0.05, 1.0);
  requirePositive("inlier_distance_m", inlier_distance_m);
  requireInRange("min_inlier_ratio", min_inlier_ratio, 0.0, 1.0);
  requireInRange("sketch_margin_m", sketch_margin_m, 0.0, 1e6);
  requireInRange("min_points", min_points, 1, 1000000);
  requireInRange("reverse_range_m", reverse_range_m, 0.0, 1e4);
}

ScaleIcp::ScaleIcp(const Points2d& sketch_points_m, const ScaleIcpConfig& config)
    : config_(config) {
  config_.validate();
  PointKdTree2d::Points pts;
  box_min_ = Eigen::Vector2d::Constant(1e300);
  box_max_ = -box_min_;
  for (const auto& p : sketch_points_m) {
    if (!p.allFinite()) continue;
    pts.push_back(p);
    box_min_ = box_min_.cwiseMin(p);
    box_max_ = box_max_.cwiseMax(p);
  }
  box_min_.array() -= config_.sketch_margin_m;
  box_max_.array() += config_.sketch_margin_m;
  tree_.reset(std::move(pts));
}

namespace {
struct Pair {
  double d_world;
  Eigen::Vector2d c, p;
};
}  // namespace

namespace {
/// Trimmed mean of the `ratio` smallest values and the fraction of values <= `inlier`.
std::pair<double, double> trimmedMean(std::vector<double>& d, double ratio, double inlier) {
  const size_t keep = std::max<size_t>(1, static_cast<size_t>(ratio * d.size()));
  std::nth_element(d.begin(), d.begin() + static_cast<long>(keep - 1), d.end());
  double sum = 0.0;
  size_t inliers = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    if (i < keep) sum += d[i];
    inliers += d[i] <= inlier;
  }
  return {sum / static_cast<double>(keep), static_cast<double>(inliers) / d.size()};
}
}  // namespace

IcpResult ScaleIcp::evaluate(const Sim2& T, const Points2d& observed,
                             const ObservedIndex* reverse) const {
  IcpResult r;
  r.T_world_sketch = T;
  if (tree_.size() == 0 || !T.isFinite() || !(T.scale > 0.0)) return r;
  const Sim2 inv = T.inverse();
  std::vector<double> d;
  d.reserve(observed.size());
  for (const auto& p : observed) {
    const Eigen::Vector2d q = inv.apply(p);
    if ((q.array() < box_min_.array()).any() || (q.array() > box_max_.array()).any()) continue;
    d.push_back(T.scale * std::sqrt(tree_.nearest(q).second));
  }
  r.num_points = static_cast<int>(d.size());
  if (r.num_points < config_.min_points) return r;
  const auto fwd = trimmedMean(d, config_.fitness_trim_ratio, config_.inlier_distance_m);
  r.forward_fitness_m = fwd.first;
  r.fitness_m = fwd.first;
  r.inlier_ratio = fwd.second;
  if (reverse && reverse->tree && reverse->tree->size() > 0 && config_.reverse_range_m > 0.0) {
    // Sketch points that the robot would see under T (HPR in the sketch frame, range mapped by
    // the scale) must have been observed.
    const Eigen::Vector2d q = inv.apply(reverse->robot_world_m);
    const double range_sketch = config_.reverse_range_m / T.scale;
    Points2d nearby;
    for (const auto& [idx, d2] : tree_.radius(q, range_sketch)) {
      (void)d2;
      nearby.push_back(tree_.points()[idx]);
    }
    HprConfig hpr;
    hpr.max_range_m = range_sketch;
    hpr.min_range_m = std::min(0.2 / T.scale, 0.5 * range_sketch);
    hpr.point_radius_m = 0.1;
    const Points2d visible = hiddenPointRemoval(nearby, q, hpr);
    std::vector<double> dr;
    dr.reserve(visible.size());
    for (const auto& c : visible) {
      dr.push_back(std::sqrt(reverse->tree->nearest(T.apply(c)).second));
    }
    if (static_cast<int>(dr.size()) >= config_.min_points) {
      const auto rev = trimmedMean(dr, config_.fitness_trim_ratio, config_.inlier_distance_m);
      r.reverse_fitness_m = rev.first;
      r.fitness_m = 0.5 * (fwd.first + rev.first);
      r.inlier_ratio = std::min(fwd.second, rev.second);
    }
  }
  r.valid = r.inlier_ratio >= config_.min_inlier_ratio;
  return r;
}

IcpResult ScaleIcp::refine(const Sim2& T_init, const Points2d& observed,
                           double start_correspondence_m, const ObservedIndex* reverse) const {
  Sim2 T = T_init;
  IcpResult out;
  if (tree_.size() == 0 || !T.isFinite() || !(T.scale > 0.0)) {
    return evaluate(T, observed, reverse);
  }
  double max_corr = start_correspondence_m > 0.0
                        ? std::max(start_correspondence_m, config_.min_correspondence_m)
                        : config_.max_correspondence_m;
  std::vector<Pair> pairs;
  pairs.reserve(observed.size());
  int it = 0;
  for (; it < config_.max_iterations; ++it) {
    const Sim2 inv = T.inverse();
    pairs.clear();
    for (const auto& p : observed) {
      const Eigen::Vector2d q = inv.apply(p);
      if ((q.array() < box_min_.array()).any() || (q.array() > box_max_.array()).any()) continue;
      const auto nn = tree_.nearest(q);
      const double d = T.scale * std::sqrt(nn.second);
      if (d <= max_corr) pairs.push_back({d, tree_.points()[nn.first], p});
    }
    if (static_cast<int>(pairs.size()) < config_.min_points) break;
    const size_t keep = std::max<size_t>(3, static_cast<size_t>(config_.trim_ratio * pairs.size()));
    if (keep < pairs.size()) {
      std::nth_element(pairs.begin(), pairs.begin() + static_cast<long>(keep), pairs.end(),
                       [](const Pair& a, const Pair& b) { return a.d_world < b.d_world; });
      pairs.resize(keep);
    }
    Points2d c(pairs.size()), p(pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i) {
      c[i] = pairs[i].c;
      p[i] = pairs[i].p;
    }
    const double s_lo = std::max(config_.scale_min, T.scale * (1.0 - config_.max_scale_step));
    const double s_hi = std::min(config_.scale_max, T.scale * (1.0 + config_.max_scale_step));
    const Sim2Fit fit = fitSim2(c, p, T.reflected, std::min(s_lo, s_hi), std::max(s_lo, s_hi));
    if (!fit.ok) break;
    // Motion of the observed centroid's preimage: one number for rotation, scale and shift.
    Eigen::Vector2d cm = Eigen::Vector2d::Zero();
    for (const auto& q : c) cm += q;
    cm /= static_cast<double>(c.size());
    const double moved = (fit.T_world_sketch.apply(cm) - T.apply(cm)).norm() +
                         std::abs(angleDiff(fit.T_world_sketch.yaw_rad, T.yaw_rad)) * 10.0 +
                         std::abs(fit.T_world_sketch.scale / T.scale - 1.0) * 10.0;
    T = fit.T_world_sketch;
    max_corr = std::max(config_.min_correspondence_m, max_corr * config_.anneal_factor);
    if (moved < config_.convergence_m && max_corr <= config_.min_correspondence_m) {
      ++it;
      break;
    }
  }
  out = evaluate(T, observed, reverse);
  out.iterations = it;
  return out;
}

}  // namespace efs::registration
