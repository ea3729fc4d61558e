// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/scale_icp.h"

#include <algorithm>
#include <cmath>
#include <tuple>

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
  requireInRange("max_stretch", max_stretch, 1.0, 2.0);
  requirePositive("convergence_m", convergence_m);
  requirePositive("anneal_when_moved_m", anneal_when_moved_m);
  requireInRange("fitness_trim_ratio", fitness_trim_ratio, 0.05, 1.0);
  requirePositive("inlier_distance_m", inlier_distance_m);
  requireInRange("min_inlier_ratio", min_inlier_ratio, 0.0, 1.0);
  requireInRange("forward_inlier_slack", forward_inlier_slack, 0.0, min_inlier_ratio);
  requireInRange("slack_min_reverse_ratio", slack_min_reverse_ratio, 0.0, 1.0);
  requireInRange("sketch_margin_m", sketch_margin_m, 0.0, 1e6);
  requireInRange("min_points", min_points, 1, 1000000);
  requireInRange("min_inside_ratio", min_inside_ratio, 0.0, 1.0);
  requireInRange("iteration_points", iteration_points, 0, 10000000);
  requireInRange("reverse_range_m", reverse_range_m, 0.0, 1e4);
  requireInRange("reverse_extent_bins", reverse_extent_bins, 0, 100000);
  requireInRange("reverse_extent_margin_m", reverse_extent_margin_m, 0.0, 1e4);
  requireInRange("coarse_yaw_steps", coarse_yaw_steps, 0, 100);
  requireInRange("coarse_yaw_step_rad", coarse_yaw_step_rad, 0.0, M_PI);
  requireInRange("coarse_scale_steps", coarse_scale_steps, 0, 100);
  requireInRange("coarse_scale_step", coarse_scale_step, 0.0, 0.9);
  requireInRange("coarse_points", coarse_points, 10, 1000000);
  requirePositive("coarse_truncation_m", coarse_truncation_m);
}

bool ScaleIcpConfig::inliersPass(const IcpResult& r, double bound) const {
  if (!r.reverse_inlier_ratio) return r.forward_inlier_ratio >= bound;
  const double rev = *r.reverse_inlier_ratio;
  const double slack = rev >= slack_min_reverse_ratio ? forward_inlier_slack : 0.0;
  return rev >= bound && r.forward_inlier_ratio >= bound - slack;
}

namespace {
/// Bounding box of the finite points, grown by margin_m; empty (min > max) without points.
std::pair<Eigen::Vector2d, Eigen::Vector2d> extentOf(const PointKdTree2d::Points& points,
                                                     double margin_m) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300);
  Eigen::Vector2d hi = -lo;
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {lo.array() - margin_m, hi.array() + margin_m};
}
}  // namespace

SketchWalls::SketchWalls(PointKdTree2d::Points points_m, const Eigen::Vector2d& box_min_m,
                         const Eigen::Vector2d& box_max_m)
    : nearest_(std::move(points_m), box_min_m, box_max_m) {
  const Eigen::Vector2d extent = box_max_m - box_min_m;
  // Without points or a proper box every bound is 0 (nx_ = ny_ = 0: nothing is skipped).
  if (nearest_.size() == 0 || !box_min_m.allFinite() || !extent.allFinite() ||
      !(extent.minCoeff() > 0.0)) {
    return;
  }
  // Twice the nearest-point grid's cells: a quarter of its cell count to build, and the bound
  // (the cell centre's distance less the half-diagonal) still within a cell or two of the truth
  // where it matters, a capture radius of metres.
  const double cell = 2.0 * nearest_.cellSize();
  const auto count = [&](double span) { return std::max(1.0, std::ceil(span / cell)); };
  min_m_ = box_min_m;
  inv_cell_ = 1.0 / cell;
  nx_ = count(extent.x());
  ny_ = count(extent.y());
  const size_t nx = static_cast<size_t>(nx_), ny = static_cast<size_t>(ny_);
  clearance_m_.resize(nx * ny);
  // A query assigned to a cell lies within the half-diagonal of its centre, give or take the
  // rounding of the cell index, which the relative and absolute slack cover many times over.
  const double reach = 0.5 * std::sqrt(2.0) * cell * (1.0 + 1e-9) + 1e-9 * cell;
  for (size_t iy = 0; iy < ny; ++iy) {
    for (size_t ix = 0; ix < nx; ++ix) {
      const Eigen::Vector2d c = min_m_ + cell * Eigen::Vector2d(ix + 0.5, iy + 0.5);
      const double bound = std::sqrt(nearest_.tree().nearest(c).second) * (1.0 - 1e-9) - reach;
      float f = static_cast<float>(std::max(0.0, bound));
      if (f > bound) f = std::max(0.0f, std::nextafter(f, 0.0f));
      clearance_m_[iy * nx + ix] = f;
    }
  }
}

ScaleIcp::SketchIndex ScaleIcp::indexSketch(const Points2d& sketch_points_m, double margin_m) {
  PointKdTree2d::Points pts;
  for (const auto& p : sketch_points_m) {
    if (p.allFinite()) pts.push_back(p);
  }
  const auto [lo, hi] = extentOf(pts, margin_m);
  return std::make_shared<const SketchWalls>(std::move(pts), lo, hi);
}

ScaleIcp::ScaleIcp(const Points2d& sketch_points_m, const ScaleIcpConfig& config)
    : ScaleIcp(indexSketch(sketch_points_m, config.sketch_margin_m), config) {}

ScaleIcp::ScaleIcp(SketchIndex sketch, const ScaleIcpConfig& config)
    : config_(config), sketch_(std::move(sketch)) {
  config_.validate();
  if (!sketch_) sketch_ = std::make_shared<const SketchWalls>();
  std::tie(box_min_, box_max_) = extentOf(sketch_->nearest().points(), config_.sketch_margin_m);
}

namespace {
struct Pair {
  double d_world;
  Eigen::Vector2d c, p;
};
}  // namespace

namespace {
/// A transform's matrices, computed once: Sim2::apply recomputes them (sines and cosines, and
/// with a stretch a second rotation) for every point, and these loops map thousands.
class Mapping {
 public:
  explicit Mapping(const Sim2& T)
      : T_(T),
        linear_(T.linear()),
        inverse_(T.inverse()),
        inverse_linear_(inverse_.linear()),
        min_gain_(T.scale * std::min(T.stretch, 1.0 / T.stretch)) {}
  Eigen::Vector2d toWorld(const Eigen::Vector2d& c) const { return linear_ * c + T_.t_m; }
  Eigen::Vector2d toSketch(const Eigen::Vector2d& p) const {
    return inverse_linear_ * p + inverse_.t_m;
  }
  /// World distance from `p` to the sketch point `c` nearest (in the sketch frame, `d2_sketch`
  /// away) to its preimage. For a similarity that is the sketch distance times the scale; a
  /// stretch makes it depend on the direction.
  double worldDistance(const Eigen::Vector2d& c, double d2_sketch, const Eigen::Vector2d& p) const {
    return T_.isSimilarity() ? T_.scale * std::sqrt(d2_sketch) : (toWorld(c) - p).norm();
  }
  /// A lower bound of worldDistance() for a query whose preimage lies at least
  /// `clearance_sketch_m` from every sketch point: the linear part's smallest gain (scale /
  /// stretch) times that, less a micrometre for the rounding of the preimage.
  double worldDistanceAtLeast(double clearance_sketch_m) const {
    return min_gain_ * (clearance_sketch_m - 1e-6);
  }

 private:
  Sim2 T_;
  Eigen::Matrix2d linear_;
  Sim2 inverse_;
  Eigen::Matrix2d inverse_linear_;
  double min_gain_;
};

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

Sim2 ScaleIcp::coarseSearch(const Sim2& T0, const Points2d& observed,
                            const ObservedIndex* reverse) const {
  const size_t n = std::min(observed.size(), static_cast<size_t>(config_.coarse_points));
  const double step = static_cast<double>(observed.size()) / static_cast<double>(n);
  Points2d sample;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < n; ++i) {
    sample.push_back(observed[static_cast<size_t>(i * step)]);
    centroid += sample.back();
  }
  centroid /= static_cast<double>(n);
  const double cap = config_.coarse_truncation_m;
  const NearestPointGrid2d& grid = sketch_->nearest();
  Points2d visible0;
  if (reverse && reverse->tree && reverse->tree->size() > 0 && config_.reverse_range_m > 0.0) {
    const Points2d all = visibleSketch(T0, reverse->robot_world_m);
    const double vstep = std::max(1.0, static_cast<double>(all.size()) / static_cast<double>(n));
    for (double k = 0; k < static_cast<double>(all.size()); k += vstep) {
      visible0.push_back(all[static_cast<size_t>(k)]);
    }
  }
  auto cost = [&](const Sim2& T) {
    const Mapping m(T);
    double sum = 0.0;
    for (const auto& p : sample) {
      const Eigen::Vector2d q = m.toSketch(p);
      if ((q.array() < box_min_.array()).any() || (q.array() > box_max_.array()).any()) {
        sum += cap;
        continue;
      }
      // Beyond the cap wherever the nearest wall is: the cap, as the search would give.
      if (m.worldDistanceAtLeast(sketch_->clearanceAtLeast(q)) > cap) {
        sum += cap;
        continue;
      }
      const auto nn = grid.nearest(q);
      sum += std::min(cap, m.worldDistance(grid.points()[nn.first], nn.second, p));
    }
    double cost = sum / static_cast<double>(sample.size());
    // One-sided distances favour a smaller scale (denser sketch walls are always near); the
    // visible-sketch -> observation side penalises walls the LiDAR did not see. Visibility is
    // taken once at T0: the grid moves walls by metres, not what is in view.
    if (!visible0.empty()) {
      double rsum = 0.0;
      for (const auto& c : visible0) {
        rsum += std::min(cap, std::sqrt(reverse->tree->nearest(m.toWorld(c)).second));
      }
      cost += rsum / static_cast<double>(visible0.size());
    }
    return cost;
  };
  Sim2 best = T0;
  double best_cost = cost(T0);
  for (int i = -config_.coarse_yaw_steps; i <= config_.coarse_yaw_steps; ++i) {
    for (int j = -config_.coarse_scale_steps; j <= config_.coarse_scale_steps; ++j) {
      if (i == 0 && j == 0) continue;
      const double ds = 1.0 + j * config_.coarse_scale_step;
      const double s = T0.scale * ds;
      if (s < config_.scale_min || s > config_.scale_max) continue;
      // Rotate and scale about the observed centroid, which stays where it is.
      const double dyaw = i * config_.coarse_yaw_step_rad;
      const Sim2 about(dyaw, ds, centroid - ds * (Eigen::Rotation2Dd(dyaw) * centroid));
      const Sim2 T = about * T0;
      const double c = cost(T);
      if (c < best_cost) {
        best_cost = c;
        best = T;
      }
    }
  }
  return best;
}

Points2d ScaleIcp::visibleSketch(const Sim2& T, const Eigen::Vector2d& robot_world_m) const {
  const Eigen::Vector2d q = T.inverse().apply(robot_world_m);
  const double range_sketch = config_.reverse_range_m / T.scale;
  Points2d nearby;
  const NearestPointGrid2d& grid = sketch_->nearest();
  for (const auto& [idx, d2] : grid.tree().radius(q, range_sketch)) {
    (void)d2;
    nearby.push_back(grid.points()[idx]);
  }
  HprConfig hpr;
  hpr.max_range_m = range_sketch;
  hpr.min_range_m = std::min(0.2 / T.scale, 0.5 * range_sketch);
  hpr.point_radius_m = 0.1;
  return hiddenPointRemoval(nearby, q, hpr);
}

IcpResult ScaleIcp::evaluate(const Sim2& T, const Points2d& observed, const ObservedIndex* reverse,
                             double drawing_reach_m) const {
  IcpResult r;
  r.T_world_sketch = T;
  const NearestPointGrid2d& grid = sketch_->nearest();
  if (grid.size() == 0 || !T.isFinite() || !(T.scale > 0.0)) return r;
  const Mapping m(T);
  std::vector<double> d;
  d.reserve(observed.size());
  for (const auto& p : observed) {
    const Eigen::Vector2d q = m.toSketch(p);
    if ((q.array() < box_min_.array()).any() || (q.array() > box_max_.array()).any()) continue;
    if (drawing_reach_m > 0.0 &&
        m.worldDistanceAtLeast(sketch_->clearanceAtLeast(q)) > drawing_reach_m) {
      continue;
    }
    const auto nn = grid.nearest(q);
    const double d_m = m.worldDistance(grid.points()[nn.first], nn.second, p);
    if (drawing_reach_m > 0.0 && d_m > drawing_reach_m) continue;
    d.push_back(d_m);
  }
  r.num_points = static_cast<int>(d.size());
  if (r.num_points < config_.min_points) return r;
  // Observations mostly outside the sketch: the transform put the sketch somewhere else (valid
  // says so), or the robot walked beyond a partial sketch (the caller decides which it believes).
  r.inside_ratio = static_cast<double>(d.size()) / static_cast<double>(observed.size());
  const auto fwd = trimmedMean(d, config_.fitness_trim_ratio, config_.inlier_distance_m);
  r.coverage = fwd.second * static_cast<double>(d.size()) / static_cast<double>(observed.size());
  r.forward_fitness_m = fwd.first;
  r.fitness_m = fwd.first;
  r.forward_inlier_ratio = fwd.second;
  if (reverse && reverse->tree && reverse->tree->size() > 0 && config_.reverse_range_m > 0.0) {
    // Sketch points that the robot would see under T (HPR in the sketch frame, range mapped by
    // the scale) must have been observed.
    const Points2d visible = visibleSketch(T, reverse->robot_world_m);
    const int bins = config_.reverse_extent_bins;
    std::vector<double> extent(static_cast<size_t>(std::max(bins, 1)), 0.0);
    const auto binOf = [&](const Eigen::Vector2d& d) {
      const double a = std::atan2(d.y(), d.x()) + M_PI;
      return std::min(bins - 1, static_cast<int>(a / (2.0 * M_PI) * bins));
    };
    if (bins > 0) {
      for (const auto& o : reverse->tree->points()) {
        const Eigen::Vector2d d = o - reverse->robot_world_m;
        double& e = extent[static_cast<size_t>(binOf(d))];
        e = std::max(e, d.norm());
      }
    }
    std::vector<double> dr;
    dr.reserve(visible.size());
    for (const auto& c : visible) {
      const Eigen::Vector2d w = m.toWorld(c);
      if (bins > 0) {
        const Eigen::Vector2d d = w - reverse->robot_world_m;
        const int b = binOf(d);
        const double reach =
            std::max({extent[static_cast<size_t>((b + bins - 1) % bins)],
                      extent[static_cast<size_t>(b)], extent[static_cast<size_t>((b + 1) % bins)]});
        if (d.norm() > reach + config_.reverse_extent_margin_m) continue;
      }
      dr.push_back(std::sqrt(reverse->tree->nearest(w).second));
    }
    if (static_cast<int>(dr.size()) >= config_.min_points) {
      const auto rev = trimmedMean(dr, config_.fitness_trim_ratio, config_.inlier_distance_m);
      r.reverse_fitness_m = rev.first;
      r.fitness_m = 0.5 * (fwd.first + rev.first);
      r.reverse_inlier_ratio = rev.second;
    }
  }
  r.usable = true;
  r.valid = config_.inliersPass(r, config_.min_inlier_ratio) &&
            r.inside_ratio >= config_.min_inside_ratio;
  return r;
}

HistoryFit ScaleIcp::historyFit(const Sim2& T, const Points2d& remembered) const {
  HistoryFit h;
  const NearestPointGrid2d& grid = sketch_->nearest();
  if (grid.size() == 0 || !T.isFinite() || !(T.scale > 0.0)) return h;
  const Mapping m(T);
  for (const auto& p : remembered) {
    ++h.points;
    const Eigen::Vector2d q = m.toSketch(p);
    if ((q.array() < box_min_.array()).any() || (q.array() > box_max_.array()).any()) continue;
    ++h.inside;
    if (m.worldDistanceAtLeast(sketch_->clearanceAtLeast(q)) > config_.inlier_distance_m) continue;
    const auto nn = grid.nearest(q);
    h.explained +=
        m.worldDistance(grid.points()[nn.first], nn.second, p) <= config_.inlier_distance_m;
  }
  return h;
}

IcpResult ScaleIcp::refine(const Sim2& T_init, const Points2d& observed,
                           double start_correspondence_m, const ObservedIndex* reverse) const {
  Sim2 T = T_init;
  IcpResult out;
  const NearestPointGrid2d& grid = sketch_->nearest();
  if (grid.size() == 0 || !T.isFinite() || !(T.scale > 0.0)) {
    return evaluate(T, observed, reverse);
  }
  if (start_correspondence_m <= 0.0 &&
      (config_.coarse_yaw_steps > 0 || config_.coarse_scale_steps > 0) && !observed.empty()) {
    T = coarseSearch(T, observed, reverse);
  }
  double max_corr = start_correspondence_m > 0.0
                        ? std::max(start_correspondence_m, config_.min_correspondence_m)
                        : config_.max_correspondence_m;
  // Iterate on an even subset; the final fitness uses every point.
  Points2d subset;
  const Points2d* iter_points = &observed;
  if (config_.iteration_points > 0 &&
      observed.size() > static_cast<size_t>(config_.iteration_points)) {
    const double st = static_cast<double>(observed.size()) / config_.iteration_points;
    for (int i = 0; i < config_.iteration_points; ++i)
      subset.push_back(observed[static_cast<size_t>(i * st)]);
    iter_points = &subset;
  }
  std::vector<Pair> pairs;
  pairs.reserve(iter_points->size());
  int it = 0;
  for (; it < config_.max_iterations; ++it) {
    const Mapping m(T);
    pairs.clear();
    for (const auto& p : *iter_points) {
      const Eigen::Vector2d q = m.toSketch(p);
      if ((q.array() < box_min_.array()).any() || (q.array() > box_max_.array()).any()) continue;
      // No wall within the capture radius: no pair, as the search would conclude.
      if (m.worldDistanceAtLeast(sketch_->clearanceAtLeast(q)) > max_corr) continue;
      const auto nn = grid.nearest(q);
      const double d = m.worldDistance(grid.points()[nn.first], nn.second, p);
      if (d <= max_corr) pairs.push_back({d, grid.points()[nn.first], p});
    }
    if (static_cast<int>(pairs.size()) < config_.min_points) break;
    if (config_.symmetric && reverse && reverse->tree && reverse->tree->size() > 0 &&
        config_.reverse_range_m > 0.0) {
      // Symmetric ICP: sketch walls the robot would see under T pull toward observed points too,
      // which keeps walls hidden in the sketch from capturing observed points.
      for (const auto& c : visibleSketch(T, reverse->robot_world_m)) {
        const Eigen::Vector2d tc = m.toWorld(c);
        const auto nn = reverse->tree->nearest(tc);
        const double d = std::sqrt(nn.second);
        if (d <= max_corr) pairs.push_back({d, c, reverse->tree->points()[nn.first]});
      }
    }
    const size_t keep = std::max<size_t>(3, static_cast<size_t>(config_.trim_ratio * pairs.size()));
    if (keep < pairs.size()) {
      std::nth_element(pairs.begin(), pairs.begin() + static_cast<long>(keep), pairs.end(),
                       [](const Pair& a, const Pair& b) { return a.d_world < b.d_world; });
      pairs.resize(keep);
    }
    Points2d c(pairs.size()), p(pairs.size());
    std::vector<double> w(pairs.size());
    // Cauchy weights whose width follows the capture radius (graduated non-convexity): wide
    // early so that a far start is pulled in by all walls, narrow late for accuracy.
    const double sigma2 = 0.25 * max_corr * max_corr;
    for (size_t i = 0; i < pairs.size(); ++i) {
      c[i] = pairs[i].c;
      p[i] = pairs[i].p;
      w[i] = 1.0 / (1.0 + pairs[i].d_world * pairs[i].d_world / sigma2);
    }
    const double s_lo = std::max(config_.scale_min, T.scale * (1.0 - config_.max_scale_step));
    const double s_hi = std::min(config_.scale_max, T.scale * (1.0 + config_.max_scale_step));
    // The stretch is refined only at the final capture radius: from a far start, distant pairs
    // would pull it (and with it the rest) into a wrong minimum. Until then it is held.
    const bool stretch_free = config_.max_stretch > 1.0 && max_corr <= config_.min_correspondence_m;
    const double stretch_max = stretch_free ? config_.max_stretch : 1.0;
    const Sim2Fit fit = fitStretchedSim2(c, p, T.reflected, std::min(s_lo, s_hi),
                                         std::max(s_lo, s_hi), stretch_max, &w, &T);
    if (!fit.ok) break;
    // Motion of the observed centroid's preimage: one number for rotation, scale and shift.
    Eigen::Vector2d cm = Eigen::Vector2d::Zero();
    for (const auto& q : c) cm += q;
    cm /= static_cast<double>(c.size());
    const double moved = (fit.T_world_sketch.apply(cm) - T.apply(cm)).norm() +
                         std::abs(angleDiff(fit.T_world_sketch.yaw_rad, T.yaw_rad)) * 10.0 +
                         std::abs(fit.T_world_sketch.scale / T.scale - 1.0) * 10.0 +
                         std::abs(fit.T_world_sketch.stretch - T.stretch) * 10.0;
    T = fit.T_world_sketch;
    // Narrow the capture radius only once the transform settles at the current one: shrinking it
    // early freezes a far-off start in a local minimum.
    if (moved < config_.anneal_when_moved_m) {
      if (max_corr <= config_.min_correspondence_m && moved < config_.convergence_m) {
        if (iter_points != &observed) {
          // Converged on the subset: polish on every point.
          iter_points = &observed;
          continue;
        }
        ++it;
        break;
      }
      max_corr = std::max(config_.min_correspondence_m, max_corr * config_.anneal_factor);
    }
  }
  out = evaluate(T, observed, reverse);
  out.iterations = it;
  // A fit that ends pinned to a scale bound wants a scale outside the allowed range: it is an
  // artefact of the clamp (e.g. a shrunken sketch laid over a repetitive floor), not a fit.
  if (config_.reject_scale_at_bound &&
      (T.scale <= config_.scale_min * (1.0 + kScaleBoundTolerance) ||
       T.scale >= config_.scale_max * (1.0 - kScaleBoundTolerance))) {
    out.valid = false;
    out.usable = false;
    out.scale_at_bound = true;
  }
  return out;
}

}  // namespace efs::registration
