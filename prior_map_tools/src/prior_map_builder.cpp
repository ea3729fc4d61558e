// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/prior_map_builder.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace efs::prior_map {

void PriorMapConfig::validate() const {
  load.validate();
  traversable.validate();
  skeleton.validate();
  guidepoints.validate();
  prm.validate();
}

namespace {

// Points every `spacing_px` along each skeleton branch: they sit on the medial axis, so they
// thread the roadmap through every door and narrow passage. Those on a filled island (the
// skeleton crosses small ones, skeleton_graph.h) are left out.
std::vector<Eigen::Vector2d> skeletonSeeds(const SkeletonGraph& g, const cv::Mat1b& region,
                                           const SketchFrame& frame, double spacing_px) {
  std::vector<Eigen::Vector2d> out;
  for (const auto& b : g.branches) {
    double since = spacing_px;  // emit the first pixel
    for (size_t i = 0; i < b.pixels.size(); ++i) {
      if (i > 0) {
        const auto &p = b.pixels[i - 1], &q = b.pixels[i];
        since += (p.x != q.x && p.y != q.y) ? M_SQRT2 : 1.0;
      }
      if (since >= spacing_px || i + 1 == b.pixels.size()) {
        const cv::Point& p = b.pixels[i];
        if (region(p.y, p.x)) out.push_back(frame.pixelCenter(p.x, p.y));
        since = 0.0;
      }
    }
  }
  // Branch ends are shared by neighbouring branches; keep one copy.
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

PriorBundle buildPriorBundle(const LoadedSketch& sketch, const PriorMapConfig& config) {
  config.validate();
  PriorBundle b;
  b.source_path = sketch.source_path;
  b.kind = sketch.kind;
  b.frame = sketch.frame;
  b.wall_mask = sketch.wall_mask.clone();
  b.mapping_range_m = config.guidepoints.mapping_range_m;

  const TraversableRegion region = extractTraversable(sketch, config.traversable);
  b.traversable = region.mask;
  const SkeletonGraph skeleton =
      extractSkeleton(region.mask, sketch.frame.m_per_px, config.skeleton);
  b.skeleton = skeleton.mask;
  b.guidepoints = sampleGuidepoints(skeleton, region, sketch.frame, config.guidepoints);

  std::vector<Eigen::Vector2d> seeds;
  for (const auto& g : b.guidepoints) seeds.push_back(g.position_m);
  const auto along = skeletonSeeds(skeleton, region.mask, sketch.frame,
                                   0.5 * config.prm.node_spacing_m / sketch.frame.m_per_px);
  seeds.insert(seeds.end(), along.begin(), along.end());
  b.prm = buildPrm(region.mask, sketch.frame, config.prm, seeds);
  b.distances = computeGuidepointDistances(b.prm, b.guidepoints, region.mask, sketch.frame);
  return b;
}

PriorMapSummary summarize(const PriorBundle& b) {
  PriorMapSummary s;
  const double px_area = b.frame.m_per_px * b.frame.m_per_px;
  s.region_area_m2 = cv::countNonZero(b.traversable) * px_area;
  cv::Mat1i labels;
  s.components =
      b.traversable.empty() ? 0 : cv::connectedComponents(b.traversable, labels, 8, CV_32S) - 1;
  const SkeletonGraph g = buildSkeletonGraph(b.skeleton);
  s.skeleton_length_m = g.totalLengthPx() * b.frame.m_per_px;
  s.skeleton_branches = static_cast<int>(g.branches.size());
  s.guidepoints = static_cast<int>(b.guidepoints.size());
  s.prm_nodes = static_cast<int>(b.prm.nodes_m.size());
  s.prm_edges = static_cast<int>(b.prm.edges.size());
  for (int i = 0; i < b.distances.size(); ++i) {
    for (int j = i + 1; j < b.distances.size(); ++j)
      s.unreachable_pairs += !b.distances.reachable(i, j);
  }
  return s;
}

cv::Mat renderOverlay(const PriorBundle& b) {
  const int longest = std::max(b.frame.width_px, b.frame.height_px);
  const double zoom = longest < 1000 ? std::ceil(1000.0 / longest) : 1.0;
  const cv::Size size(static_cast<int>(b.frame.width_px * zoom),
                      static_cast<int>(b.frame.height_px * zoom));
  cv::Mat3b img(size, cv::Vec3b(255, 255, 255));
  cv::Mat1b trav, wall, skel;
  cv::resize(b.traversable, trav, size, 0, 0, cv::INTER_NEAREST);
  cv::resize(b.wall_mask, wall, size, 0, 0, cv::INTER_NEAREST);
  img.setTo(cv::Vec3b(205, 240, 205), trav);
  img.setTo(cv::Vec3b(40, 40, 40), wall);
  auto toPx = [&](const Eigen::Vector2d& p_m) {
    const Eigen::Vector2d px = b.frame.toPixel(p_m) * zoom;
    return cv::Point(static_cast<int>(px.x()), static_cast<int>(px.y()));
  };
  for (const auto& e : b.prm.edges) {
    cv::line(img, toPx(b.prm.nodes_m[e.a]), toPx(b.prm.nodes_m[e.b]), cv::Scalar(230, 190, 150), 1,
             cv::LINE_AA);
  }
  std::vector<cv::Point> sk;
  if (!b.skeleton.empty()) cv::findNonZero(b.skeleton, sk);
  for (const auto& p : sk) {
    const cv::Point c(static_cast<int>((p.x + 0.5) * zoom), static_cast<int>((p.y + 0.5) * zoom));
    cv::circle(img, c, std::max(1, static_cast<int>(zoom / 2)), cv::Scalar(40, 40, 220),
               cv::FILLED);
  }
  const int r = std::max(5, static_cast<int>(3 * zoom));
  for (const auto& g : b.guidepoints) {
    const cv::Point c = toPx(g.position_m);
    cv::circle(img, c, r, cv::Scalar(0, 140, 255), cv::FILLED, cv::LINE_AA);
    cv::circle(img, c, r, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    cv::putText(img, std::to_string(g.id), c + cv::Point(r + 2, -r), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                cv::Scalar(120, 0, 0), 1, cv::LINE_AA);
  }
  return img;
}

}  // namespace efs::prior_map
