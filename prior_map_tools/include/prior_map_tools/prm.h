// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Probabilistic roadmap over the traversable region (paper Sec. IV-A) and the guidepoint distance
// matrix computed on it with Dijkstra (Sec. IV-C).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <opencv2/core.hpp>
#include <vector>

#include "prior_map_tools/guidepoints.h"
#include "prior_map_tools/sketch_frame.h"

namespace efs::prior_map {

struct PrmConfig {
  /// Mean spacing of uniformly sampled nodes [m]: one node per spacing^2 of region area.
  double node_spacing_m = 1.5;
  /// Each node is joined to its k nearest neighbours where the straight edge is collision free.
  int k_neighbours = 10;
  /// Upper bound on the number of nodes (memory bound for huge sketches).
  int max_nodes = 200000;
  uint64_t seed = 1;

  void validate() const;
};

struct PrmEdge {
  int a = 0, b = 0;
  double length_m = 0.0;
};

struct Prm {
  std::vector<Eigen::Vector2d> nodes_m;  ///< sketch frame
  std::vector<PrmEdge> edges;            ///< undirected, a < b, no duplicates
  /// Adjacency lists: for node i, (neighbour, edge length).
  std::vector<std::vector<std::pair<int, double>>> adjacency() const;
};

/// Samples and connects the roadmap; edges are checked against `region` (255 = traversable).
/// `seed_nodes_m` become the first nodes, in order (the builder passes the guidepoints and
/// points along the skeleton, which runs through every door: uniform samples alone can miss a
/// narrow passage and split the roadmap).
Prm buildPrm(const cv::Mat1b& region, const SketchFrame& frame, const PrmConfig& config,
             const std::vector<Eigen::Vector2d>& seed_nodes_m = {});

/// True if the straight segment between two metric points stays on traversable pixels.
bool segmentTraversable(const cv::Mat1b& region, const SketchFrame& frame,
                        const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m);

/// Symmetric matrix of shortest traversable path lengths between guidepoints [sketch m].
/// Pairs with no connecting path are unreachable, stored as +infinity and reported by
/// reachable(); they are never given a finite "large number".
class DistanceMatrix {
 public:
  static constexpr double kUnreachable = std::numeric_limits<double>::infinity();

  DistanceMatrix() = default;
  explicit DistanceMatrix(int n) : n_(n), d_(static_cast<size_t>(n) * n, kUnreachable) {
    for (int i = 0; i < n; ++i) set(i, i, 0.0);
  }

  int size() const { return n_; }
  double at(int i, int j) const { return d_[static_cast<size_t>(i) * n_ + j]; }
  bool reachable(int i, int j) const { return at(i, j) < kUnreachable; }
  void set(int i, int j, double v) { d_[static_cast<size_t>(i) * n_ + j] = v; }
  const std::vector<double>& data() const { return d_; }

 private:
  int n_ = 0;
  std::vector<double> d_;
};

/// Dijkstra from every guidepoint over the PRM. A guidepoint joins the roadmap through the
/// nearest nodes it sees along a traversable straight segment.
DistanceMatrix computeGuidepointDistances(const Prm& prm,
                                          const std::vector<Guidepoint>& guidepoints,
                                          const cv::Mat1b& region, const SketchFrame& frame);

}  // namespace efs::prior_map
