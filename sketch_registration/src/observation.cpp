// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/observation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "efs_common/config_check.h"
#include "efs_common/voxel_key.h"

namespace efs::registration {

void ObservationConfig::validate() const {
  requireThat(std::isfinite(slice_min_dz_m) && std::isfinite(slice_max_dz_m) &&
                  slice_min_dz_m < slice_max_dz_m,
              "slice_min_dz_m", "must be finite and < slice_max_dz_m");
  requireInRange("column_cell_m", column_cell_m, 0.01, 10.0);
  requireInRange("wall_min_height_m", wall_min_height_m, 0.0, 100.0);
  requireInRange("wall_max_gap_m", wall_max_gap_m, 0.01, 100.0);
  requireInRange("wall_top_clear_m", wall_top_clear_m, -100.0, 100.0);
  requireInRange("wall_continuation_m", wall_continuation_m, 0.0, 100.0);
  requireThat(wall_continuation_m == 0.0 || wall_continuation_m > kContinuationMinDz,
              "wall_continuation_m",
              "must be 0 (no low-obstacle test) or above kContinuationMinDz (0.1 m)");
  requirePositive("icp_voxel_m", icp_voxel_m);
  requirePositive("icp_range_m", icp_range_m);
  requireInRange("icp_max_points", icp_max_points, 10, 10000000);
}

namespace {

struct CellIndex {
  long long ix, iy;
};

CellIndex cellIndex(const Eigen::Vector2d& d, double cell_m) {
  return {static_cast<long long>(std::floor(d.x() / cell_m)),
          static_cast<long long>(std::floor(d.y() / cell_m))};
}

/// The band's points within range, binned into vertical columns in the order the columns are
/// first met (thinning downstream keeps the first point of a cell). Heights live in one flat
/// array grouped by column, not in a vector per column: a paper-size garage frame holds ~270k
/// points in ~30k columns, and the allocations per column took as long as the hashing.
class ColumnGrid {
 public:
  ColumnGrid(const Points3d& local_map, const Eigen::Vector3d& robot,
             const ObservationConfig& config, double range_m, ProjectedMap& counts) {
    index_.reserve(local_map.size() / 4 + 16);
    std::vector<uint32_t> column_of;
    std::vector<float> z_of;
    column_of.reserve(local_map.size());
    z_of.reserve(local_map.size());
    const double r2 = range_m * range_m;
    for (const auto& p : local_map) {
      if (!p.allFinite()) {
        ++counts.num_non_finite;
        continue;
      }
      const double dz = p.z() - robot.z();
      if (dz < config.slice_min_dz_m || dz > config.slice_max_dz_m) continue;
      const Eigen::Vector2d d = p.head<2>() - robot.head<2>();
      if (d.squaredNorm() > r2) continue;
      ++counts.num_in_band;
      const CellIndex cell = cellIndex(d, config.column_cell_m);
      const auto [it, added] =
          index_.emplace(cellKey2d(cell.ix, cell.iy), static_cast<uint32_t>(sum_m_.size()));
      if (added) {
        sum_m_.emplace_back(Eigen::Vector2d::Zero());
        cells_.push_back(cell);
      }
      sum_m_[it->second] += p.head<2>();
      column_of.push_back(it->second);
      z_of.push_back(static_cast<float>(p.z()));
    }
    const size_t n = sum_m_.size();
    begin_.assign(n + 1, 0);
    for (uint32_t c : column_of) ++begin_[c + 1];
    for (size_t c = 0; c < n; ++c) begin_[c + 1] += begin_[c];
    z_m_.resize(z_of.size());
    std::vector<size_t> next(begin_.begin(), begin_.end() - 1);
    for (size_t i = 0; i < column_of.size(); ++i) z_m_[next[column_of[i]]++] = z_of[i];
  }

  size_t size() const { return sum_m_.size(); }
  Eigen::Vector2d mean(size_t c) const {
    return sum_m_[c] / static_cast<double>(begin_[c + 1] - begin_[c]);
  }
  void sortHeights() {
    for (size_t c = 0; c < size(); ++c) std::sort(heightsBegin(c), heightsEnd(c));
  }
  float* heightsBegin(size_t c) { return z_m_.data() + begin_[c]; }
  float* heightsEnd(size_t c) { return z_m_.data() + begin_[c + 1]; }
  const float* heightsBegin(size_t c) const { return z_m_.data() + begin_[c]; }
  const float* heightsEnd(size_t c) const { return z_m_.data() + begin_[c + 1]; }

  /// The highest point of each block of kBlockColumns x kBlockColumns columns. Heights sorted.
  std::unordered_map<long long, float> highestPerBlock() const {
    std::unordered_map<long long, float> top;
    top.reserve(size() / 8 + 16);
    for (size_t c = 0; c < size(); ++c) {
      const auto [it, added] = top.emplace(blockKey(cells_[c], 0, 0), *(heightsEnd(c) - 1));
      if (!added) it->second = std::max(it->second, *(heightsEnd(c) - 1));
    }
    return top;
  }
  /// The highest point in the 3 x 3 blocks around column `c`'s block: the ceiling beside it where
  /// one was seen, else no higher than the column's own top.
  double highestAround(size_t c, const std::unordered_map<long long, float>& top) const {
    double z = -std::numeric_limits<double>::infinity();
    for (long long dx = -1; dx <= 1; ++dx) {
      for (long long dy = -1; dy <= 1; ++dy) {
        const auto it = top.find(blockKey(cells_[c], dx, dy));
        if (it != top.end()) z = std::max(z, static_cast<double>(it->second));
      }
    }
    return z;
  }

  /// Whether a column next to `c` (8-neighbourhood) holds a height in (z_lo, z_hi]. Heights
  /// sorted.
  bool neighbourHoldsHeightIn(size_t c, double z_lo, double z_hi) const {
    const CellIndex cell = cells_[c];
    for (long long dx = -1; dx <= 1; ++dx) {
      for (long long dy = -1; dy <= 1; ++dy) {
        if (dx == 0 && dy == 0) continue;
        const auto it = index_.find(cellKey2d(cell.ix + dx, cell.iy + dy));
        if (it == index_.end()) continue;
        const float* end = heightsEnd(it->second);
        const float* above = std::upper_bound(heightsBegin(it->second), end, float(z_lo));
        if (above != end && *above <= z_hi) return true;
      }
    }
    return false;
  }

 private:
  /// Blocks of columns for the ceiling lookup: 4 x 0.25 m columns, so the 3 x 3 blocks around a
  /// column reach 1-2 m from it.
  static constexpr long long kBlockColumns = 4;
  static long long blockOf(long long i) {
    return i >= 0 ? i / kBlockColumns : -((-i + kBlockColumns - 1) / kBlockColumns);
  }
  static long long blockKey(const CellIndex& cell, long long dx, long long dy) {
    return cellKey2d(blockOf(cell.ix) + dx, blockOf(cell.iy) + dy);
  }

  std::unordered_map<long long, uint32_t> index_;
  std::vector<CellIndex> cells_;
  std::vector<Eigen::Vector2d> sum_m_;
  std::vector<size_t> begin_;
  std::vector<float> z_m_;
};

enum class ColumnKind : uint8_t { kWall, kPassage, kOther, kLowObstacle };

/// Wall, passage or other from the column's own sorted heights (see the header).
ColumnKind classifyOwnHeights(const float* lo, const float* hi, const ObservationConfig& config) {
  double max_gap = 0.0;
  for (const float* z = lo + 1; z < hi; ++z) {
    max_gap = std::max(max_gap, static_cast<double>(*z - *(z - 1)));
  }
  if (max_gap > config.wall_max_gap_m) return ColumnKind::kPassage;
  if (*(hi - 1) - *lo >= config.wall_min_height_m) return ColumnKind::kWall;
  return ColumnKind::kOther;
}

}  // namespace

long long gridCellKey(const Eigen::Vector2d& d, double cell_m) {
  const CellIndex c = cellIndex(d, cell_m);
  return cellKey2d(c.ix, c.iy);
}

ProjectedMap observeLocalMap(const Points3d& local_map, const Eigen::Vector3d& robot,
                             const ObservationConfig& config, double range_m) {
  ProjectedMap out;
  out.num_input = local_map.size();
  ColumnGrid grid(local_map, robot, config, range_m, out);
  const size_t n = grid.size();
  out.num_columns = n;
  if (!config.wall_columns) {
    for (size_t c = 0; c < n; ++c) out.points_m.push_back(grid.mean(c));
    return out;
  }
  grid.sortHeights();
  std::vector<ColumnKind> kind(n);
  for (size_t c = 0; c < n; ++c) {
    kind[c] = classifyOwnHeights(grid.heightsBegin(c), grid.heightsEnd(c), config);
  }
  if (config.wall_continuation_m > 0.0) {
    const double clear_top_m = robot.z() + config.wall_top_clear_m;
    const std::unordered_map<long long, float> ceiling = grid.highestPerBlock();
    for (size_t c = 0; c < n; ++c) {
      if (kind[c] != ColumnKind::kWall) continue;
      const double top_m = *(grid.heightsEnd(c) - 1);
      const bool open_above =
          top_m < clear_top_m || top_m < grid.highestAround(c, ceiling) - config.wall_max_gap_m;
      if (open_above && !grid.neighbourHoldsHeightIn(c, top_m + kContinuationMinDz,
                                                     top_m + config.wall_continuation_m)) {
        kind[c] = ColumnKind::kLowObstacle;
      }
    }
  }
  for (size_t c = 0; c < n; ++c) {
    switch (kind[c]) {
      case ColumnKind::kWall:
        out.points_m.push_back(grid.mean(c));
        break;
      case ColumnKind::kPassage:
        ++out.num_passage_columns;
        out.passage_m.push_back(grid.mean(c));
        break;
      case ColumnKind::kLowObstacle:
        ++out.num_low_obstacle_columns;
        out.other_m.push_back(grid.mean(c));
        break;
      case ColumnKind::kOther:
        out.other_m.push_back(grid.mean(c));
        break;
    }
  }
  return out;
}

Points2d thinToGrid(const Points2d& points, const Eigen::Vector2d& centre, double range_m,
                    double voxel_m) {
  std::unordered_set<long long> seen;
  seen.reserve(points.size() + 16);
  Points2d out;
  const double r2 = range_m * range_m;
  for (const auto& p : points) {
    const Eigen::Vector2d d = p - centre;
    if (d.squaredNorm() > r2) continue;
    if (seen.insert(gridCellKey(d, voxel_m)).second) out.push_back(p);
  }
  return out;
}

Points2d thinEvenly(const Points2d& points, size_t max_points) {
  if (points.size() <= max_points || max_points == 0) return points;
  Points2d out;
  out.reserve(max_points);
  const double step = static_cast<double>(points.size()) / static_cast<double>(max_points);
  for (size_t i = 0; i < max_points; ++i) out.push_back(points[static_cast<size_t>(i * step)]);
  return out;
}

Observation observe(const Points3d& local_map, const Eigen::Vector3d& robot,
                    const ObservationConfig& config, double descriptor_range_m) {
  Observation o;
  o.map =
      observeLocalMap(local_map, robot, config, std::max(descriptor_range_m, config.icp_range_m));
  const Eigen::Vector2d xy = robot.head<2>();
  o.descriptor_m = thinToGrid(o.map.points_m, xy, descriptor_range_m, config.column_cell_m);
  o.icp_dense_m = thinToGrid(o.map.points_m, xy, config.icp_range_m, config.icp_voxel_m);
  o.icp_m = thinEvenly(o.icp_dense_m, static_cast<size_t>(config.icp_max_points));
  o.passage_m = thinToGrid(o.map.passage_m, xy, config.icp_range_m, config.column_cell_m);
  return o;
}

}  // namespace efs::registration
