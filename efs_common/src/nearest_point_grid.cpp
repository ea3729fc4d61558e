// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/nearest_point_grid.h"

#include <algorithm>
#include <cmath>

namespace efs {

namespace {

/// Median distance from a point to its nearest other point, over an even sample.
double medianSpacing(const PointKdTree2d& tree) {
  const auto& pts = tree.points();
  const size_t step = std::max<size_t>(1, pts.size() / 1000);
  std::vector<double> d;
  for (size_t i = 0; i < pts.size(); i += step) {
    const auto nn = tree.knn(pts[i], 2);
    if (nn.size() == 2) d.push_back(std::sqrt(nn[1].second));
  }
  if (d.empty()) return 0.0;
  std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace

NearestPointGrid2d::NearestPointGrid2d(Points points, const Eigen::Vector2d& box_min_m,
                                       const Eigen::Vector2d& box_max_m,
                                       const NearestPointGridConfig& config) {
  tree_.reset(std::move(points));
  const Eigen::Vector2d extent = box_max_m - box_min_m;
  // Without points or a proper box every query goes to the tree (nx_ = ny_ = 0).
  if (tree_.size() == 0 || !box_min_m.allFinite() || !extent.allFinite() ||
      !(extent.minCoeff() > 0.0) || config.max_cells == 0 || config.max_list == 0) {
    return;
  }
  double cell = config.cell_m > 0.0 ? config.cell_m : 2.0 * medianSpacing(tree_);
  cell = std::max(cell, std::sqrt(extent.x() * extent.y() / static_cast<double>(config.max_cells)));
  if (!(cell > 0.0) || !std::isfinite(cell)) return;
  const auto count = [&](double c, double span) { return std::max(1.0, std::ceil(span / c)); };
  while (count(cell, extent.x()) * count(cell, extent.y()) > static_cast<double>(config.max_cells))
    cell *= 1.05;
  min_m_ = box_min_m;
  cell_m_ = cell;
  inv_cell_ = 1.0 / cell;
  nx_ = count(cell, extent.x());
  ny_ = count(cell, extent.y());
  const size_t nx = static_cast<size_t>(nx_), ny = static_cast<size_t>(ny_);
  begin_.assign(nx * ny + 1, 0);
  // Any query q in a cell of centre c and half-diagonal h has its nearest point within
  // |q - c| + d0 <= h + d0 of q, hence within d0 + 2h of c (d0: c's nearest-point distance).
  const double h = 0.5 * std::sqrt(2.0) * cell;
  for (size_t iy = 0; iy < ny; ++iy) {
    for (size_t ix = 0; ix < nx; ++ix) {
      const Eigen::Vector2d c = min_m_ + cell * Eigen::Vector2d(ix + 0.5, iy + 0.5);
      const auto near = tree_.knn(c, config.max_list + 1);
      const double r = std::sqrt(near.front().second) + 2.0 * h;
      // A hair wider than the bound, so that rounding never drops the true nearest point.
      const double r2 = std::pow(r * (1.0 + 1e-12) + 1e-12 * cell, 2);
      const size_t cell_index = iy * nx + ix;
      if (near.size() > config.max_list && near.back().second <= r2) {
        begin_[cell_index + 1] = static_cast<uint32_t>(list_.size());
        continue;
      }
      for (const auto& [index, d2] : near) {
        if (d2 <= r2) list_.push_back(static_cast<uint32_t>(index));
      }
      begin_[cell_index + 1] = static_cast<uint32_t>(list_.size());
    }
  }
  list_.shrink_to_fit();
}

size_t NearestPointGrid2d::numListedCells() const {
  size_t n = 0;
  for (size_t c = 0; c + 1 < begin_.size(); ++c) n += begin_[c + 1] > begin_[c];
  return n;
}

}  // namespace efs
