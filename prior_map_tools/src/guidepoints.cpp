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

// Geodesic distance along the skeleton (8-connected pixel steps) from a set of source pixels,
// relaxed into `dist` (so repeated calls accumulate the minimum over all sources).
void relaxSkeletonDistance(const cv::Mat1b& skeleton, const std::vector<cv::Point>& sources,
                           cv::Mat1f* dist) {
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  for (const auto& p : sources) {
    if (!skeleton(p.y, p.x)) continue;
    (*dist)(p.y, p.x) = 0.0f;
    open.emplace(0.0f, p.y * skeleton.cols + p.x);
  }
  while (!open.empty()) {
    const auto [d, idx] = open.top();
    open.pop();
    const int x = idx % skeleton.cols, y = idx / skeleton.cols;
    if (d > (*dist)(y, x)) continue;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx, ny = y + dy;
        if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= skeleton.cols || ny >= skeleton.rows)
          continue;
        if (!skeleton(ny, nx)) continue;
        const float nd = d + ((dx != 0 && dy != 0) ? static_cast<float>(M_SQRT2) : 1.0f);
        if (nd < (*dist)(ny, nx)) {
          (*dist)(ny, nx) = nd;
          open.emplace(nd, ny * skeleton.cols + nx);
        }
      }
    }
  }
}

void coverSkeletonGaps(const cv::Mat1b& skeleton, const TraversableRegion& region,
                       double max_gap_px, double min_separation_px, const SketchFrame& frame,
                       std::vector<Guidepoint>* out, std::vector<cv::Point>* out_px) {
  cv::Mat1f dist(skeleton.size(), std::numeric_limits<float>::infinity());
  relaxSkeletonDistance(skeleton, *out_px, &dist);
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
    const int comp = region.components(at.y, at.x);
    bool too_close = comp <= 0;
    for (const auto& q : *out_px)
      too_close = too_close || std::hypot(q.x - at.x, q.y - at.y) < min_separation_px;
    if (!too_close) {
      Guidepoint g;
      g.id = static_cast<uint32_t>(out->size());
      g.position_m = frame.pixelCenter(at.x, at.y);
      g.component = comp;
      g.branch = Guidepoint::kNoBranch;
      out->push_back(g);
      out_px->push_back(at);
    }
    // Either way this pixel is settled: it now has a guidepoint at or near it.
    relaxSkeletonDistance(skeleton, {at}, &dist);
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

  auto add = [&](const cv::Point& px, int branch) {
    const int comp = region.components(px.y, px.x);
    if (comp <= 0) return;  // skeleton pixel outside the kept region (a dropped speck)
    // Two branches meeting at a short junction can propose nearly the same place.
    for (const auto& q : out_px) {
      if (std::hypot(q.x - px.x, q.y - px.y) < 0.5 * range_px) return;
    }
    Guidepoint g;
    g.id = static_cast<uint32_t>(out.size());
    g.position_m = frame.pixelCenter(px.x, px.y);
    g.component = comp;
    g.branch = branch;
    out.push_back(g);
    out_px.push_back(px);
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
    Guidepoint g;
    g.id = static_cast<uint32_t>(out.size());
    g.position_m = frame.pixelCenter(best.x, best.y);
    g.component = comp;
    g.branch = Guidepoint::kNoBranch;
    out.push_back(g);
    out_px.push_back(best);
  }
  return out;
}

}  // namespace efs::prior_map
