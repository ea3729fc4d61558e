// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Exact nearest-point queries on a static 2D point set, answered from a grid of candidate lists.
// Scale-ICP and its screen ask the sketch ~10^6 times a frame on the paper-size garage; the k-d
// tree answers each in ~70 ns, a short list scan in a fraction of that. Queries outside the grid,
// and in cells far from every point (whose lists would be long), go to the k-d tree: the answer
// is the same either way.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "efs_common/point_kdtree.h"

namespace efs {

struct NearestPointGridConfig {
  /// Cell side in the points' units. 0: twice the median point spacing, enlarged until the grid
  /// has at most max_cells cells.
  double cell_m = 0.0;
  size_t max_cells = size_t{1} << 17;
  /// A cell whose candidate list would be longer answers through the k-d tree instead.
  size_t max_list = 32;
};

class NearestPointGrid2d {
 public:
  using Points = PointKdTree2d::Points;

  NearestPointGrid2d() = default;
  /// Builds the k-d tree over `points` and the grid over [box_min_m, box_max_m].
  NearestPointGrid2d(Points points, const Eigen::Vector2d& box_min_m,
                     const Eigen::Vector2d& box_max_m, const NearestPointGridConfig& config = {});

  size_t size() const { return tree_.size(); }
  const Points& points() const { return tree_.points(); }
  const PointKdTree2d& tree() const { return tree_; }

  /// Nearest point: (index, squared distance); size() must be > 0. Equal to tree().nearest(q)
  /// up to which of several equidistant points is named.
  std::pair<size_t, double> nearest(const Eigen::Vector2d& q) const {
    const double fx = (q.x() - min_m_.x()) * inv_cell_;
    const double fy = (q.y() - min_m_.y()) * inv_cell_;
    // Written so that NaN fails too.
    if (!(fx >= 0.0 && fy >= 0.0 && fx < nx_ && fy < ny_)) return tree_.nearest(q);
    const size_t cell =
        static_cast<size_t>(fy) * static_cast<size_t>(nx_) + static_cast<size_t>(fx);
    const uint32_t b = begin_[cell], e = begin_[cell + 1];
    if (b == e) return tree_.nearest(q);
    const Points& pts = tree_.points();
    size_t best = list_[b];
    double best_d2 = (pts[best] - q).squaredNorm();
    for (uint32_t k = b + 1; k < e; ++k) {
      const double d2 = (pts[list_[k]] - q).squaredNorm();
      if (d2 < best_d2) {
        best_d2 = d2;
        best = list_[k];
      }
    }
    return {best, best_d2};
  }

  double cellSize() const { return cell_m_; }
  size_t numCells() const { return begin_.empty() ? 0 : begin_.size() - 1; }
  /// Cells answered from their list (the others go to the k-d tree).
  size_t numListedCells() const;

 private:
  PointKdTree2d tree_;
  Eigen::Vector2d min_m_ = Eigen::Vector2d::Zero();
  double cell_m_ = 1.0, inv_cell_ = 1.0;
  double nx_ = 0.0, ny_ = 0.0;   ///< cell counts, as doubles for the range test
  std::vector<uint32_t> begin_;  ///< list of cell c: list_[begin_[c] .. begin_[c + 1])
  std::vector<uint32_t> list_;
};

}  // namespace efs
