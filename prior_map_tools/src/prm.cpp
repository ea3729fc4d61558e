// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/prm.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <queue>
#include <random>
#include <set>

#include "efs_common/config_check.h"
#include "efs_common/point_kdtree.h"

namespace efs::prior_map {

void PrmConfig::validate() const {
  requirePositive("node_spacing_m", node_spacing_m);
  requireInRange("node_spacing_m", node_spacing_m, 1e-3, 1000.0);
  requireInRange("k_neighbours", k_neighbours, 1, 64);
  requireInRange("max_nodes", max_nodes, 1, 10 * 1000 * 1000);
}

std::vector<std::vector<std::pair<int, double>>> Prm::adjacency() const {
  std::vector<std::vector<std::pair<int, double>>> adj(nodes_m.size());
  for (const auto& e : edges) {
    adj[e.a].emplace_back(e.b, e.length_m);
    adj[e.b].emplace_back(e.a, e.length_m);
  }
  return adj;
}

bool segmentTraversable(const cv::Mat1b& region, const SketchFrame& frame,
                        const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m) {
  const Eigen::Vector2d pa = frame.toPixel(a_m), pb = frame.toPixel(b_m);
  const cv::Point ia(static_cast<int>(std::floor(pa.x())), static_cast<int>(std::floor(pa.y())));
  const cv::Point ib(static_cast<int>(std::floor(pb.x())), static_cast<int>(std::floor(pb.y())));
  const cv::Rect bounds(0, 0, region.cols, region.rows);
  if (!bounds.contains(ia) || !bounds.contains(ib)) return false;
  // 4-connected rasterisation: a diagonal step cannot slip between two touching obstacle pixels.
  cv::LineIterator it(region, ia, ib, 4);
  for (int i = 0; i < it.count; ++i, ++it) {
    if (**it == 0) return false;
  }
  return true;
}

namespace {

// Union-find over roadmap nodes.
int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Nodes whose k nearest neighbours all lie behind a corner, or a pocket of the region reached
// through a pinch that no edge to the k nearest crosses, leave the roadmap in pieces inside one
// region component: a guidepoint there was unreachable from every other (seen in ed21's sketch 2
// once the inside of free-standing loops stopped being traversable, which moved the samples).
// Each piece is joined to the largest through the first of its nodes that sees one of its kJoin
// nearest nodes there. A pocket behind a pinch no straight edge crosses stays apart (one
// guidepoint of the Pittsburgh mine's precise drawing).
void joinStrandedNodes(const cv::Mat1b& region, const SketchFrame& frame, Prm* prm) {
  constexpr size_t kJoin = 16;
  const int n = static_cast<int>(prm->nodes_m.size());
  std::vector<int> parent(n);
  for (int i = 0; i < n; ++i) parent[i] = i;
  for (const PrmEdge& e : prm->edges) parent[findRoot(parent, e.a)] = findRoot(parent, e.b);
  std::vector<int> size(n, 0);
  for (int i = 0; i < n; ++i) ++size[findRoot(parent, i)];
  const int largest = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
  if (size[largest] == n) return;
  std::vector<int> main_ids;
  PointKdTree2d::Points main_pts;
  for (int i = 0; i < n; ++i) {
    if (findRoot(parent, i) != largest) continue;
    main_ids.push_back(i);
    main_pts.push_back(prm->nodes_m[i]);
  }
  const PointKdTree2d main_tree(std::move(main_pts));
  for (int i = 0; i < n; ++i) {
    if (findRoot(parent, i) == largest) continue;
    for (const auto& [k, d2] : main_tree.knn(prm->nodes_m[i], kJoin)) {
      const int j = main_ids[k];
      if (d2 <= 0.0 || !segmentTraversable(region, frame, prm->nodes_m[i], prm->nodes_m[j]))
        continue;
      prm->edges.push_back({std::min(i, j), std::max(i, j), std::sqrt(d2)});
      parent[findRoot(parent, i)] = largest;  // the largest piece's root stays its root
      break;
    }
  }
}

}  // namespace

Prm buildPrm(const cv::Mat1b& region, const SketchFrame& frame, const PrmConfig& config,
             const std::vector<Eigen::Vector2d>& seed_nodes_m) {
  config.validate();
  Prm prm;
  std::vector<cv::Point> free_px;
  cv::findNonZero(region, free_px);
  const double area_m2 = free_px.size() * frame.m_per_px * frame.m_per_px;
  const int wanted =
      std::clamp(static_cast<int>(area_m2 / (config.node_spacing_m * config.node_spacing_m)), 0,
                 std::max(0, config.max_nodes - static_cast<int>(seed_nodes_m.size())));

  for (const auto& s : seed_nodes_m) prm.nodes_m.push_back(s);
  std::mt19937_64 rng(config.seed);
  if (!free_px.empty()) {
    std::uniform_int_distribution<size_t> pick(0, free_px.size() - 1);
    std::uniform_real_distribution<double> jitter(0.0, 1.0);
    for (int i = 0; i < wanted; ++i) {
      const cv::Point& p = free_px[pick(rng)];
      // Uniform within the pixel, so the node set is uniform over the region's area.
      const Eigen::Vector2d c = frame.pixelCenter(p.x, p.y);
      prm.nodes_m.push_back(c +
                            frame.m_per_px * Eigen::Vector2d(jitter(rng) - 0.5, jitter(rng) - 0.5));
    }
  }
  if (prm.nodes_m.size() < 2) return prm;

  PointKdTree2d::Points pts(prm.nodes_m.begin(), prm.nodes_m.end());
  const PointKdTree2d tree(std::move(pts));
  std::set<std::pair<int, int>> seen;
  const size_t k = static_cast<size_t>(config.k_neighbours) + 1;  // the query node itself
  for (size_t i = 0; i < prm.nodes_m.size(); ++i) {
    for (const auto& [j, d2] : tree.knn(prm.nodes_m[i], k)) {
      if (j == i || d2 <= 0.0) continue;
      const int a = static_cast<int>(std::min(i, j)), b = static_cast<int>(std::max(i, j));
      if (!seen.insert({a, b}).second) continue;
      if (!segmentTraversable(region, frame, prm.nodes_m[a], prm.nodes_m[b])) continue;
      prm.edges.push_back({a, b, std::sqrt(d2)});
    }
  }
  joinStrandedNodes(region, frame, &prm);
  return prm;
}

DistanceMatrix computeGuidepointDistances(const Prm& prm,
                                          const std::vector<Guidepoint>& guidepoints,
                                          const cv::Mat1b& region, const SketchFrame& frame) {
  const int n = static_cast<int>(guidepoints.size());
  DistanceMatrix dm(n);
  if (n == 0 || prm.nodes_m.empty()) return dm;
  const auto adj = prm.adjacency();
  PointKdTree2d::Points pts(prm.nodes_m.begin(), prm.nodes_m.end());
  const PointKdTree2d tree(std::move(pts));

  // Each guidepoint enters the roadmap through the nearest nodes it sees directly.
  constexpr size_t kAttach = 8;
  std::vector<std::vector<std::pair<int, double>>> attach(n);
  for (int g = 0; g < n; ++g) {
    for (const auto& [j, d2] : tree.knn(guidepoints[g].position_m, kAttach)) {
      if (d2 == 0.0 ||
          segmentTraversable(region, frame, guidepoints[g].position_m, prm.nodes_m[j])) {
        attach[g].emplace_back(static_cast<int>(j), std::sqrt(d2));
      }
    }
  }

  const size_t nn = prm.nodes_m.size();
  std::vector<double> dist(nn);
  using Item = std::pair<double, int>;
  for (int g = 0; g < n; ++g) {
    std::fill(dist.begin(), dist.end(), DistanceMatrix::kUnreachable);
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
    for (const auto& [j, d] : attach[g]) {
      if (d < dist[j]) {
        dist[j] = d;
        open.emplace(d, j);
      }
    }
    while (!open.empty()) {
      const auto [d, u] = open.top();
      open.pop();
      if (d > dist[u]) continue;
      for (const auto& [v, w] : adj[u]) {
        if (d + w < dist[v]) {
          dist[v] = d + w;
          open.emplace(dist[v], v);
        }
      }
    }
    for (int h = 0; h < n; ++h) {
      if (h == g) continue;
      double best = DistanceMatrix::kUnreachable;
      for (const auto& [j, d] : attach[h]) best = std::min(best, dist[j] + d);
      // Straight line of sight between the two guidepoints is also a path.
      if (segmentTraversable(region, frame, guidepoints[g].position_m, guidepoints[h].position_m)) {
        best = std::min(best, (guidepoints[g].position_m - guidepoints[h].position_m).norm());
      }
      dm.set(g, h, best);
    }
  }
  // Dijkstra from either end gives the same value up to rounding; make it exactly symmetric.
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double v = std::min(dm.at(i, j), dm.at(j, i));
      dm.set(i, j, v);
      dm.set(j, i, v);
    }
  }
  // The line-of-sight shortcuts are not roadmap paths, so close the matrix under concatenation
  // (Floyd-Warshall): every entry is still the length of a real path, and the triangle
  // inequality holds exactly, which the planner's costs rely on.
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < n; ++i) {
      const double dik = dm.at(i, k);
      if (dik == DistanceMatrix::kUnreachable) continue;
      for (int j = 0; j < n; ++j) {
        const double via = dik + dm.at(k, j);
        if (via < dm.at(i, j)) dm.set(i, j, via);
      }
    }
  }
  return dm;
}

}  // namespace efs::prior_map
