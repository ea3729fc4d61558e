// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Topological skeleton of the traversable region (paper Sec. IV-B): small islands filled, then
// Zhang-Suen thinning, then a graph of junctions/endpoints joined by pixel chains, with short
// spurs pruned.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace efs::prior_map {

struct SkeletonConfig {
  /// Islands (obstacles enclosed by the region) no wider or taller than this are filled before
  /// thinning [m]. The robot sees around a pillar whichever side it passes, so a pillar is no
  /// topology; unfilled, every pillar of a drawn garage put a loop in the skeleton and the
  /// 192 x 150 m garage got 233 guidepoints on a mesh of short branches (the paper: 20-30
  /// guidepoints per world). Only the skeleton sees the filled islands. 0 = off.
  double max_island_extent_m = 4.0;
  /// Terminal branches shorter than this are spurs of corners and wall noise [m].
  double spur_prune_length_m = 2.0;
  /// Pruning passes (a pruned spur can expose another).
  int prune_iterations = 3;

  void validate() const;
};

struct SkeletonBranch {
  std::vector<cv::Point> pixels;  ///< ordered chain, first/last are the end nodes' pixels
  int node_a = 0;                 ///< index into SkeletonGraph::nodes
  int node_b = 0;
  double length_px = 0.0;
};

struct SkeletonNode {
  cv::Point pixel;
  int degree = 0;  ///< 1 = endpoint, >= 3 = junction, 0 = isolated loop anchor
};

struct SkeletonGraph {
  cv::Mat1b mask;  ///< 255 on skeleton pixels (after pruning)
  std::vector<SkeletonNode> nodes;
  std::vector<SkeletonBranch> branches;
  double totalLengthPx() const;
};

/// `region` with its islands of at most `max_extent_px` in width and height filled (255). An
/// island is a 4-connected component of non-region pixels that does not touch the image border.
cv::Mat1b fillSmallIslands(const cv::Mat1b& region, double max_extent_px);

/// Skeleton of a binary region mask (255 = inside). `m_per_px` converts the config's lengths.
SkeletonGraph extractSkeleton(const cv::Mat1b& region, double m_per_px,
                              const SkeletonConfig& config);

/// Graph of an existing 1-pixel-wide skeleton mask (8-connected).
SkeletonGraph buildSkeletonGraph(const cv::Mat1b& skeleton_mask);

}  // namespace efs::prior_map
