// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/skeleton_graph.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc.hpp>

#include "efs_common/config_check.h"

namespace efs::prior_map {

void SkeletonConfig::validate() const {
  requireInRange("spur_prune_length_m", spur_prune_length_m, 0.0, 1000.0);
  requireInRange("prune_iterations", prune_iterations, 0, 100);
  requireInRange("max_island_extent_m", max_island_extent_m, 0.0, 1000.0);
}

cv::Mat1b fillSmallIslands(const cv::Mat1b& region, double max_extent_px) {
  cv::Mat1b out = region.clone();
  if (region.empty() || max_extent_px <= 0.0) return out;
  cv::Mat1i labels;
  cv::Mat stats, centroids;
  const cv::Mat1b outside = (region == 0);
  const int n = cv::connectedComponentsWithStats(outside, labels, stats, centroids, 4, CV_32S);
  std::vector<uint8_t> fill(static_cast<size_t>(n), 0);
  for (int i = 1; i < n; ++i) {
    const int x = stats.at<int>(i, cv::CC_STAT_LEFT), y = stats.at<int>(i, cv::CC_STAT_TOP);
    const int w = stats.at<int>(i, cv::CC_STAT_WIDTH), h = stats.at<int>(i, cv::CC_STAT_HEIGHT);
    const bool touches_border = x == 0 || y == 0 || x + w == region.cols || y + h == region.rows;
    fill[static_cast<size_t>(i)] = !touches_border && w <= max_extent_px && h <= max_extent_px;
  }
  for (int y = 0; y < region.rows; ++y)
    for (int x = 0; x < region.cols; ++x)
      if (fill[static_cast<size_t>(labels(y, x))]) out(y, x) = 255;
  return out;
}

double SkeletonGraph::totalLengthPx() const {
  double sum = 0.0;
  for (const auto& b : branches) sum += b.length_px;
  return sum;
}

namespace {

const int kDx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
const int kDy[8] = {0, -1, -1, -1, 0, 1, 1, 1};

bool on(const cv::Mat1b& m, int x, int y) {
  return x >= 0 && y >= 0 && x < m.cols && y < m.rows && m(y, x) != 0;
}

// Neighbours of a skeleton pixel in the "thin" sense: 8-neighbours, except a diagonal neighbour
// that is also reachable through a shared 4-neighbour (staircases would otherwise fake
// junctions).
int thinNeighbours(const cv::Mat1b& m, int x, int y, cv::Point* out) {
  int n = 0;
  for (int k = 0; k < 8; ++k) {
    const int nx = x + kDx[k], ny = y + kDy[k];
    if (!on(m, nx, ny)) continue;
    const bool diagonal = kDx[k] != 0 && kDy[k] != 0;
    if (diagonal && (on(m, x + kDx[k], y) || on(m, x, y + kDy[k]))) continue;
    out[n++] = cv::Point(nx, ny);
  }
  return n;
}

double stepLength(const cv::Point& a, const cv::Point& b) {
  return (a.x != b.x && a.y != b.y) ? M_SQRT2 : 1.0;
}

}  // namespace

SkeletonGraph buildSkeletonGraph(const cv::Mat1b& skeleton_mask) {
  SkeletonGraph g;
  g.mask = skeleton_mask.clone();
  const cv::Mat1b& m = g.mask;
  cv::Mat1i node_id(m.size(), -1);
  cv::Point nb[8];

  // Junction pixels that touch each other form one junction node.
  cv::Mat1b junction = cv::Mat1b::zeros(m.size());
  for (int y = 0; y < m.rows; ++y) {
    for (int x = 0; x < m.cols; ++x) {
      if (!m(y, x)) continue;
      const int d = thinNeighbours(m, x, y, nb);
      if (d >= 3) junction(y, x) = 255;
      if (d == 1 || d == 0) {
        node_id(y, x) = static_cast<int>(g.nodes.size());
        g.nodes.push_back({cv::Point(x, y), d});
      }
    }
  }
  cv::Mat1i jlabels;
  const int nj = cv::connectedComponents(junction, jlabels, 8, CV_32S);
  std::vector<int> jnode(nj, -1);
  for (int y = 0; y < m.rows; ++y) {
    for (int x = 0; x < m.cols; ++x) {
      const int l = jlabels(y, x);
      if (l == 0) continue;
      if (jnode[l] < 0) {
        jnode[l] = static_cast<int>(g.nodes.size());
        g.nodes.push_back({cv::Point(x, y), 0});
      }
      node_id(y, x) = jnode[l];
    }
  }

  // Trace chains between nodes. Each chain pixel is visited once; a chain starts at a node pixel
  // and walks through degree-2 pixels until it enters another node pixel.
  cv::Mat1b visited = cv::Mat1b::zeros(m.size());
  auto trace = [&](cv::Point start_node_px, cv::Point first) {
    SkeletonBranch br;
    br.node_a = node_id(start_node_px.y, start_node_px.x);
    br.pixels.push_back(start_node_px);
    cv::Point prev = start_node_px, cur = first;
    while (true) {
      br.length_px += stepLength(prev, cur);
      br.pixels.push_back(cur);
      const int id = node_id(cur.y, cur.x);
      if (id >= 0) {
        br.node_b = id;
        break;
      }
      visited(cur.y, cur.x) = 255;
      const int d = thinNeighbours(m, cur.x, cur.y, nb);
      cv::Point next(-1, -1);
      for (int k = 0; k < d; ++k) {
        if (nb[k] == prev) continue;
        if (visited(nb[k].y, nb[k].x) && node_id(nb[k].y, nb[k].x) < 0) continue;
        next = nb[k];
        break;
      }
      if (next.x < 0) {  // dead stop inside a chain (should not happen on a thin skeleton)
        br.node_b = static_cast<int>(g.nodes.size());
        g.nodes.push_back({cur, 1});
        node_id(cur.y, cur.x) = br.node_b;
        break;
      }
      prev = cur;
      cur = next;
    }
    return br;
  };

  for (int y = 0; y < m.rows; ++y) {
    for (int x = 0; x < m.cols; ++x) {
      if (node_id(y, x) < 0) continue;
      const int d = thinNeighbours(m, x, y, nb);
      for (int k = 0; k < d; ++k) {
        const cv::Point q = nb[k];
        if (visited(q.y, q.x)) continue;
        const int qid = node_id(q.y, q.x);
        if (qid >= 0) {
          // Adjacent node pixels: a one-step branch, recorded once (from the lower id), and not
          // at all inside one junction cluster.
          if (qid != node_id(y, x) && node_id(y, x) < qid) {
            SkeletonBranch br;
            br.node_a = node_id(y, x);
            br.node_b = qid;
            br.pixels = {cv::Point(x, y), q};
            br.length_px = stepLength(cv::Point(x, y), q);
            g.branches.push_back(br);
          }
          continue;
        }
        g.branches.push_back(trace(cv::Point(x, y), q));
      }
    }
  }
  // Closed loops with no node: anchor each at one pixel and trace around it.
  for (int y = 0; y < m.rows; ++y) {
    for (int x = 0; x < m.cols; ++x) {
      if (!m(y, x) || visited(y, x) || node_id(y, x) >= 0) continue;
      node_id(y, x) = static_cast<int>(g.nodes.size());
      g.nodes.push_back({cv::Point(x, y), 2});
      const int d = thinNeighbours(m, x, y, nb);
      if (d > 0) g.branches.push_back(trace(cv::Point(x, y), nb[0]));
    }
  }
  for (auto& n : g.nodes) n.degree = 0;
  for (const auto& b : g.branches) {
    ++g.nodes[b.node_a].degree;
    ++g.nodes[b.node_b].degree;
  }
  return g;
}

SkeletonGraph extractSkeleton(const cv::Mat1b& region, double m_per_px,
                              const SkeletonConfig& config) {
  config.validate();
  const cv::Mat1b filled = fillSmallIslands(region, config.max_island_extent_m / m_per_px);
  cv::Mat1b skeleton = cv::Mat1b::zeros(region.size());
  const cv::Rect roi = cv::boundingRect(filled);
  if (roi.area() > 0) {
    // Thinning only inside the region's bounding box (plus a margin): much faster on sketches
    // that are mostly blank paper.
    const cv::Rect padded =
        (roi + cv::Size(4, 4) - cv::Point(2, 2)) & cv::Rect(0, 0, region.cols, region.rows);
    cv::Mat1b thin;
    cv::ximgproc::thinning(filled(padded), thin, cv::ximgproc::THINNING_ZHANGSUEN);
    thin.copyTo(skeleton(padded));
  }
  const double spur_px = config.spur_prune_length_m / m_per_px;
  SkeletonGraph g = buildSkeletonGraph(skeleton);
  for (int it = 0; it < config.prune_iterations; ++it) {
    bool pruned = false;
    for (const auto& b : g.branches) {
      const int da = g.nodes[b.node_a].degree, db = g.nodes[b.node_b].degree;
      const bool spur = (da == 1 && db >= 3) || (db == 1 && da >= 3);
      if (!spur || b.length_px >= spur_px) continue;
      // Erase the spur but keep the junction pixel.
      const cv::Point junction_px = (da >= 3) ? b.pixels.front() : b.pixels.back();
      for (const auto& p : b.pixels) {
        if (p != junction_px) skeleton(p.y, p.x) = 0;
      }
      pruned = true;
    }
    if (!pruned) break;
    // Removing spurs can leave 2-pixel-thick corners at old junctions; thin again.
    cv::Mat1b rethin;
    cv::ximgproc::thinning(skeleton, rethin, cv::ximgproc::THINNING_ZHANGSUEN);
    skeleton = rethin;
    g = buildSkeletonGraph(skeleton);
  }
  return g;
}

}  // namespace efs::prior_map
