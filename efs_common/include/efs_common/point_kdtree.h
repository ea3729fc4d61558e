// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// k-d tree over a vector of Eigen points (nanoflann 1.4 API, as packaged in Debian bookworm).
// One adaptor for the whole suite: PRM neighbours, Scale-ICP correspondences, map queries.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <nanoflann.hpp>
#include <utility>
#include <vector>

namespace efs {

template <int Dim>
class PointKdTree {
 public:
  using Point = Eigen::Matrix<double, Dim, 1>;
  using Points = std::vector<Point, Eigen::aligned_allocator<Point>>;

  PointKdTree() = default;
  explicit PointKdTree(Points points) { reset(std::move(points)); }

  /// Rebuilds the tree over `points` (the tree owns its copy).
  void reset(Points points) {
    adaptor_.points = std::move(points);
    index_ = std::make_unique<Index>(Dim, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    index_->buildIndex();
  }

  size_t size() const { return adaptor_.points.size(); }
  const Points& points() const { return adaptor_.points; }

  /// Up to k nearest neighbours, closest first: (index, squared distance).
  std::vector<std::pair<size_t, double>> knn(const Point& q, size_t k) const {
    std::vector<std::pair<size_t, double>> out;
    if (!index_ || size() == 0 || k == 0) return out;
    k = std::min(k, size());
    std::vector<size_t> idx(k);
    std::vector<double> d2(k);
    const size_t found = index_->knnSearch(q.data(), k, idx.data(), d2.data());
    out.reserve(found);
    for (size_t i = 0; i < found; ++i) out.emplace_back(idx[i], d2[i]);
    return out;
  }

  /// Nearest neighbour: (index, squared distance); size() must be > 0. The result set lives on
  /// the stack: through knn() the three vectors it allocates cost as much as the search itself,
  /// and Scale-ICP and the screen ask this ~10^5 times a frame.
  std::pair<size_t, double> nearest(const Point& q) const {
    size_t index = 0;
    double d2 = 0.0;
    nanoflann::KNNResultSet<double, size_t> result(1);
    result.init(&index, &d2);
    index_->findNeighbors(result, q.data(), nanoflann::SearchParams());
    return {index, d2};
  }

  /// All points within `radius` (not squared): (index, squared distance), closest first.
  std::vector<std::pair<size_t, double>> radius(const Point& q, double radius) const {
    std::vector<std::pair<size_t, double>> out;
    if (!index_ || size() == 0) return out;
    nanoflann::SearchParams params;
    params.sorted = true;
    index_->radiusSearch(q.data(), radius * radius, out, params);
    return out;
  }

 private:
  struct Adaptor {
    Points points;
    size_t kdtree_get_point_count() const { return points.size(); }
    double kdtree_get_pt(size_t i, size_t d) const { return points[i][static_cast<int>(d)]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const {
      return false;
    }
  };
  using Index = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>,
                                                    Adaptor, Dim, size_t>;
  Adaptor adaptor_;
  std::unique_ptr<Index> index_;
};

using PointKdTree2d = PointKdTree<2>;
using PointKdTree3d = PointKdTree<3>;

}  // namespace efs
