// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/observation.h"

#include <cmath>
#include <unordered_set>

#include "efs_common/config_check.h"

namespace efs::registration {

void ObservationConfig::validate() const {
  requireThat(std::isfinite(slice_min_dz_m) && std::isfinite(slice_max_dz_m) &&
                  slice_min_dz_m < slice_max_dz_m,
              "slice_min_dz_m", "must be finite and < slice_max_dz_m");
  requirePositive("descriptor_voxel_m", descriptor_voxel_m);
  requirePositive("icp_voxel_m", icp_voxel_m);
  requirePositive("icp_range_m", icp_range_m);
  requireInRange("icp_max_points", icp_max_points, 10, 10000000);
}

ProjectedMap projectLocalMap(const Points3d& local_map, const Eigen::Vector3d& robot,
                             double min_dz_m, double max_dz_m, double range_m, double voxel_m) {
  ProjectedMap out;
  out.num_input = local_map.size();
  std::unordered_set<long long> seen;
  seen.reserve(local_map.size() / 4 + 16);
  const double r2 = range_m * range_m;
  for (const auto& p : local_map) {
    if (!p.allFinite()) {
      ++out.num_non_finite;
      continue;
    }
    const double dz = p.z() - robot.z();
    if (dz < min_dz_m || dz > max_dz_m) continue;
    const Eigen::Vector2d d = p.head<2>() - robot.head<2>();
    if (d.squaredNorm() > r2) continue;
    ++out.num_in_band;
    const long long ix = static_cast<long long>(std::floor(d.x() / voxel_m));
    const long long iy = static_cast<long long>(std::floor(d.y() / voxel_m));
    if (seen.insert((ix << 32) ^ (iy & 0xffffffffLL)).second) out.points_m.push_back(p.head<2>());
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

}  // namespace efs::registration
