// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/observation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "efs_common/config_check.h"

namespace efs::registration {

void ObservationConfig::validate() const {
  requireThat(std::isfinite(slice_min_dz_m) && std::isfinite(slice_max_dz_m) &&
                  slice_min_dz_m < slice_max_dz_m,
              "slice_min_dz_m", "must be finite and < slice_max_dz_m");
  requireInRange("column_cell_m", column_cell_m, 0.01, 10.0);
  requireInRange("wall_min_height_m", wall_min_height_m, 0.0, 100.0);
  requireInRange("wall_max_gap_m", wall_max_gap_m, 0.01, 100.0);
  requirePositive("icp_voxel_m", icp_voxel_m);
  requirePositive("icp_range_m", icp_range_m);
  requireInRange("icp_max_points", icp_max_points, 10, 10000000);
}

long long gridCellKey(const Eigen::Vector2d& d, double cell_m) {
  const long long ix = static_cast<long long>(std::floor(d.x() / cell_m));
  const long long iy = static_cast<long long>(std::floor(d.y() / cell_m));
  return (ix << 32) ^ (iy & 0xffffffffLL);
}

ProjectedMap observeLocalMap(const Points3d& local_map, const Eigen::Vector3d& robot,
                             const ObservationConfig& config, double range_m) {
  ProjectedMap out;
  out.num_input = local_map.size();
  // Columns in the order they are first met (thinning downstream keeps the first point of a
  // cell). Their heights go to one flat array grouped by column, not to a vector per column: a
  // paper-size garage frame holds ~270k points in ~30k columns, and the allocations per column
  // took as long as the hashing.
  std::unordered_map<long long, uint32_t> index;
  index.reserve(local_map.size() / 4 + 16);
  std::vector<Eigen::Vector2d> sum_m;
  std::vector<uint32_t> column_of;
  std::vector<float> z_of;
  column_of.reserve(local_map.size());
  z_of.reserve(local_map.size());
  const double r2 = range_m * range_m;
  for (const auto& p : local_map) {
    if (!p.allFinite()) {
      ++out.num_non_finite;
      continue;
    }
    const double dz = p.z() - robot.z();
    if (dz < config.slice_min_dz_m || dz > config.slice_max_dz_m) continue;
    const Eigen::Vector2d d = p.head<2>() - robot.head<2>();
    if (d.squaredNorm() > r2) continue;
    ++out.num_in_band;
    const auto [it, added] =
        index.emplace(gridCellKey(d, config.column_cell_m), static_cast<uint32_t>(sum_m.size()));
    if (added) sum_m.emplace_back(Eigen::Vector2d::Zero());
    sum_m[it->second] += p.head<2>();
    column_of.push_back(it->second);
    z_of.push_back(static_cast<float>(p.z()));
  }
  const size_t n = sum_m.size();
  out.num_columns = n;
  std::vector<size_t> begin(n + 1, 0);
  for (uint32_t c : column_of) ++begin[c + 1];
  for (size_t c = 0; c < n; ++c) begin[c + 1] += begin[c];
  std::vector<float> z_m(z_of.size());
  {
    std::vector<size_t> next(begin.begin(), begin.end() - 1);
    for (size_t i = 0; i < column_of.size(); ++i) z_m[next[column_of[i]]++] = z_of[i];
  }
  for (size_t c = 0; c < n; ++c) {
    float* lo = z_m.data() + begin[c];
    float* hi = z_m.data() + begin[c + 1];
    const Eigen::Vector2d centre = sum_m[c] / static_cast<double>(hi - lo);
    if (!config.wall_columns) {
      out.points_m.push_back(centre);
      continue;
    }
    std::sort(lo, hi);
    double max_gap = 0.0;
    for (const float* z = lo + 1; z < hi; ++z) {
      max_gap = std::max(max_gap, static_cast<double>(*z - *(z - 1)));
    }
    if (max_gap > config.wall_max_gap_m) {
      ++out.num_passage_columns;
      out.passage_m.push_back(centre);
      continue;
    }
    if (*(hi - 1) - *lo >= config.wall_min_height_m) {
      out.points_m.push_back(centre);
    } else {
      out.other_m.push_back(centre);
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
