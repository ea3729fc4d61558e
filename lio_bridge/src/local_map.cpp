// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "lio_bridge/local_map.h"

#include <cmath>

#include "efs_common/config_check.h"

namespace efs::lio {

void LocalMapConfig::validate() const {
  requireInRange("voxel_size_m", voxel_size_m, 0.01, 10.0);
  requireInRange("window_radius_m", window_radius_m, 1.0, 10000.0);
  requireInRange("max_range_m", max_range_m, 0.5, 1000.0);
}

LocalMap::LocalMap(const LocalMapConfig& config) : config_(config) { config_.validate(); }

size_t LocalMap::insert(const std::vector<Eigen::Vector3f>& points_world,
                        const Eigen::Vector3d& sensor_world_m) {
  if (!sensor_world_m.allFinite()) return 0;
  const double max_r2 = config_.max_range_m * config_.max_range_m;
  size_t used = 0;
  for (const auto& pf : points_world) {
    if (!pf.allFinite()) continue;
    const Eigen::Vector3d p = pf.cast<double>();
    if ((p - sensor_world_m).squaredNorm() > max_r2) continue;
    Cell& c = voxels_[toVoxelKey(p, config_.voxel_size_m)];
    c.sum += pf;
    ++c.count;
    ++used;
  }
  return used;
}

void LocalMap::crop(const Eigen::Vector3d& robot_world_m) {
  const double r2 = config_.window_radius_m * config_.window_radius_m;
  for (auto it = voxels_.begin(); it != voxels_.end();) {
    const Eigen::Vector3d c = voxelCenter(it->first, config_.voxel_size_m);
    if ((c.head<2>() - robot_world_m.head<2>()).squaredNorm() > r2) {
      it = voxels_.erase(it);
    } else {
      ++it;
    }
  }
}

std::vector<Eigen::Vector3f> LocalMap::points() const {
  std::vector<Eigen::Vector3f> out;
  out.reserve(voxels_.size());
  for (const auto& [key, cell] : voxels_) out.push_back(cell.sum / static_cast<float>(cell.count));
  return out;
}

FrameDecimator::FrameDecimator(double rate_hz) {
  requireInRange("registration_rate_hz", rate_hz, 1e-3, 100.0);
  period_s_ = 1.0 / rate_hz;
}

bool FrameDecimator::due(double now_s) {
  if (first_ || now_s - last_s_ >= period_s_ || now_s < last_s_) {
    first_ = false;
    last_s_ = now_s;
    return true;
  }
  return false;
}

}  // namespace efs::lio
