// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/guidepoints.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <queue>

#include "efs_common/config_check.h"

namespace efs::prior_map {

void GuidepointConfig::validate() const {
  requirePositive("mapping_range_m", mapping_range_m);
  requireInRange("mapping_range_m", mapping_range_m, 0.1, 1000.0);
  requireInRange("interval_factor", interval_factor, 0.5, 20.0);
  requireInRange("min_dead_end_factor", min_dead_end_factor, 0.0, 20.0);
  requireInRange("min_link_factor", min_link_factor, 0.0, 20.0);
  requireInRange("coverage_factor", coverage_factor, 0.1, 10.0);
  requireInRange("region_cover_factor", region_cover_factor, 0.0, 100.0);
}

namespace {

// The pixel at arc length `s` along a branch's chain.
cv::Point pointAtArcLength(const SkeletonBranch& b, double s) {
  double acc = 0.0;
  for (size_t i = 1; i < b.pixels.size(); ++i) {
    const cv::Point& p = b.pixels[i - 1];
    const cv::Point& q = b.pixels[i];
    acc += (p.x != q.x && p.y != q.y) ? M_SQRT2 : 1.0;
    if (acc >= s) return q;
  }
  return b.pixels.back();
}

// Geodesic distance within a mask (8-connected pixel steps: the skeleton, or the region) from a
// set of source pixels, relaxed into `dist` (so repeated calls accumulate the minimum over all
// sources).
void relaxGeodesicDistance(const cv::Mat1b& mask, const std::vector<cv::Point>& sources,
                           cv::Mat1f* dist) {
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  for (const auto& p : sources) {
    if (!mask(p.y, p.x)) continue;
    (*dist)(p.y, p.x) = 0.0f;
    open.emplace(0.0f, p.y * mask.cols + p.x);
  }
  while (!open.empty()) {
    const auto [d, idx] = open.top();
    open.pop();
    const int x = idx % mask.cols, y = idx / mask.cols;
    if (d > (*dist)(y, x)) continue;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= mask.cols || ny >= mask.rows)
          continue;
        if (!mask(ny, nx)) continue;
        const float nd = d + ((dx != 0 && dy != 0) ? static_cast<float>(M_SQRT2) : 1.0f);
        if (nd < (*dist)(ny, nx)) {
          (*dist)(ny, nx) = nd;
          open.emplace(nd, ny * mask.cols + nx);
        }
      }
    }
  }
}

// Appends a guidepoint at region pixel `px`.
void appendGuidepoint(const TraversableRegion& region, const SketchFrame& frame,
                      const cv::Point& px, int branch, std::vector<Guidepoint>* out,
                      std::vector<cv::Point>* out_px) {
  Guidepoint g;
  g.id = static_cast<uint32_t>(out->size());
  g.position_m = frame.pixelCenter(px.x, px.y);
  g.component = region.components(px.y, px.x);
  g.branch = branch;
  out->push_back(g);
  out_px->push_back(px);
}

// While some region pixel is farther along the region than `max_dist_px` from every guidepoint,
// one goes near the farthest: at the most open pixel (farthest from the region's edge) within
// half that distance of it, so that it stands in the open area it covers, not in its corner.
void coverRegion(const TraversableRegion& region, double max_dist_px, const SketchFrame& frame,
                 std::vector<Guidepoint>* out, std::vector<cv::Point>* out_px) {
  const cv::Mat1b inside = region.components > 0;
  cv::Mat1f dist(inside.size(), std::numeric_limits<float>::infinity());
  relaxGeodesicDistance(inside, *out_px, &dist);
  cv::Mat1f clearance;
  cv::distanceTransform(inside, clearance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  const int r = static_cast<int>(std::floor(0.5 * max_dist_px));
  while (true) {
    double worst = max_dist_px;
    cv::Point at(-1, -1);
    for (int y = 0; y < dist.rows; ++y)
      for (int x = 0; x < dist.cols; ++x) {
        const float d = dist(y, x);
        if (std::isfinite(d) && d > worst) {
          worst = d;
          at = {x, y};
        }
      }
    if (at.x < 0) break;
    cv::Point best = at;
    for (int y = std::max(0, at.y - r); y <= std::min(dist.rows - 1, at.y + r); ++y)
      for (int x = std::max(0, at.x - r); x <= std::min(dist.cols - 1, at.x + r); ++x)
        if (inside(y, x) && (x - at.x) * (x - at.x) + (y - at.y) * (y - at.y) <= r * r &&
            dist(y, x) > 0.5f * static_cast<float>(worst) && clearance(y, x) > clearance(best))
          best = {x, y};
    appendGuidepoint(region, frame, best, Guidepoint::kNoBranch, out, out_px);
    relaxGeodesicDistance(inside, {best}, &dist);
  }
}

// The region pixel nearest to `px` within `max_r_px` (the skeleton crosses islands it was
// allowed to ignore, skeleton_graph.h); (-1, -1) if none.
cv::Point ontoRegion(const TraversableRegion& region, const cv::Point& px, double max_r_px) {
  const cv::Mat1i& c = region.components;
  if (c(px.y, px.x) > 0) return px;
  const int r = static_cast<int>(std::ceil(max_r_px));
  cv::Point best(-1, -1);
  double best_d2 = max_r_px * max_r_px;
  for (int y = std::max(0, px.y - r); y <= std::min(c.rows - 1, px.y + r); ++y)
    for (int x = std::max(0, px.x - r); x <= std::min(c.cols - 1, px.x + r); ++x) {
      const double d2 = static_cast<double>((x - px.x) * (x - px.x) + (y - px.y) * (y - px.y));
      if (c(y, x) > 0 && d2 <= best_d2 && (best.x < 0 || d2 < best_d2)) {
        best_d2 = d2;
        best = {x, y};
      }
    }
  return best;
}

void coverSkeletonGaps(const cv::Mat1b& skeleton, const TraversableRegion& region,
                       double max_gap_px, double min_separation_px, const SketchFrame& frame,
                       std::vector<Guidepoint>* out, std::vector<cv::Point>* out_px) {
  cv::Mat1f dist(skeleton.size(), std::numeric_limits<float>::infinity());
  relaxGeodesicDistance(skeleton, *out_px, &dist);
  // Skeleton pieces with no guidepoint at all are handled per component below (region seeds);
  // only pixels that some guidepoint reaches, but from too far, are gaps.
  std::vector<cv::Point> pixels;
  cv::findNonZero(skeleton, pixels);
  while (true) {
    double worst = max_gap_px;
    cv::Point at(-1, -1);
    for (const auto& p : pixels) {
      const float d = dist(p.y, p.x);
      if (std::isfinite(d) && d > worst) {
        worst = d;
        at = p;
      }
    }
    if (at.x < 0) break;
    const cv::Point on = ontoRegion(region, at, min_separation_px);
    bool too_close = on.x < 0;
    for (const auto& q : *out_px)
      too_close = too_close || std::hypot(q.x - on.x, q.y - on.y) < min_separation_px;
    if (!too_close) appendGuidepoint(region, frame, on, Guidepoint::kNoBranch, out, out_px);
    // Either way this pixel is settled: it now has a guidepoint at or near it.
    relaxGeodesicDistance(skeleton, {at}, &dist);
  }
}

}  // namespace

std::vector<Guidepoint> sampleGuidepoints(const SkeletonGraph& skeleton,
                                          const TraversableRegion& region, const SketchFrame& frame,
                                          const GuidepointConfig& config) {
  config.validate();
  const double interval_px = config.intervalM() / frame.m_per_px;
  const double range_px = config.mapping_range_m / frame.m_per_px;
  std::vector<Guidepoint> out;
  std::vector<cv::Point> out_px;

  auto add = [&](const cv::Point& skeleton_px, int branch) {
    // Off the region: a filled island (moved beside it) or a dropped speck (skipped).
    const cv::Point px = ontoRegion(region, skeleton_px, 0.5 * range_px);
    if (px.x < 0) return;
    // Two branches meeting at a short junction can propose nearly the same place.
    for (const auto& q : out_px) {
      if (std::hypot(q.x - px.x, q.y - px.y) < 0.5 * range_px) return;
    }
    appendGuidepoint(region, frame, px, branch, &out, &out_px);
  };

  // Longest branches first, so that the de-duplication keeps points on the main corridors.
  std::vector<int> order(skeleton.branches.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return skeleton.branches[a].length_px > skeleton.branches[b].length_px;
  });

  for (int bi : order) {
    const SkeletonBranch& b = skeleton.branches[bi];
    const int da = skeleton.nodes[b.node_a].degree, db = skeleton.nodes[b.node_b].degree;
    const bool loop = b.node_a == b.node_b;
    const bool isolated = da <= 1 && db <= 1;  // the whole skeleton of a region
    const bool dead_end = !isolated && (da == 1 || db == 1);
    double min_len = 0.0;
    if (dead_end) min_len = config.min_dead_end_factor * range_px;
    if (!dead_end && !isolated && !loop) min_len = config.min_link_factor * range_px;
    if (b.length_px < min_len) continue;  // an intersection or a corner seen from the junction
    const int n = std::max(1, static_cast<int>(std::lround(b.length_px / interval_px)));
    for (int i = 0; i < n; ++i) {
      // Mid-points of n equal pieces: never on a junction or an endpoint. A dead end's single
      // guidepoint goes a little deeper than the middle, towards what is unseen.
      double t = loop ? static_cast<double>(i) / n : (i + 0.5) / n;
      if (dead_end && n == 1) t = 0.6;
      // Arc length from the junction end (a chain may be stored either way round).
      const double s = (dead_end && da == 1) ? (1.0 - t) * b.length_px : t * b.length_px;
      add(pointAtArcLength(b, s), bi);
    }
  }

  // Chains of short branches (a corridor with many side doors) get no guidepoint from the rule
  // above, so fill the gaps: while some skeleton pixel is farther along the skeleton than
  // `coverage_factor` x interval from every guidepoint, put one on the farthest such pixel.
  coverSkeletonGaps(skeleton.mask, region, config.coverage_factor * interval_px, 0.5 * range_px,
                    frame, &out, &out_px);

  // Independent regions whose skeleton gave nothing get one guidepoint at their widest point.
  for (int comp = 1; comp <= region.numComponents(); ++comp) {
    const bool has = std::any_of(out.begin(), out.end(),
                                 [&](const Guidepoint& g) { return g.component == comp; });
    if (has) continue;
    cv::Mat1b m = (region.components == comp);
    cv::Mat1f dist;
    cv::distanceTransform(m, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    cv::Point best;
    cv::minMaxLoc(dist, nullptr, nullptr, nullptr, &best);
    appendGuidepoint(region, frame, best, Guidepoint::kNoBranch, &out, &out_px);
  }

  if (config.region_cover_factor > 0.0)
    coverRegion(region, config.region_cover_factor * interval_px, frame, &out, &out_px);
  return out;
}

}  // namespace efs::prior_map
