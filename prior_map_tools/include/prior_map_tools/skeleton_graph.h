// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Topological skeleton of the traversable region (paper Sec. IV-B): Zhang-Suen thinning, then a
// graph of junctions/endpoints joined by pixel chains, with short spurs pruned.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace efs::prior_map {

struct SkeletonConfig {
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

/// Skeleton of a binary region mask (255 = inside). `m_per_px` converts the config's lengths.
SkeletonGraph extractSkeleton(const cv::Mat1b& region, double m_per_px,
                              const SkeletonConfig& config);

/// Graph of an existing 1-pixel-wide skeleton mask (8-connected).
SkeletonGraph buildSkeletonGraph(const cv::Mat1b& skeleton_mask);

}  // namespace efs::prior_map
