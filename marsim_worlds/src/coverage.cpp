// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/coverage.h"

#include <algorithm>
#include <cmath>

#include "efs_common/config_check.h"

namespace efs::sim {

void CoverageConfig::validate() const {
  requireInRange("voxel_size_m", voxel_size_m, 0.01, 10.0);
  requireInRange("coverage_range_m", coverage_range_m, 0.1, 1000.0);
  requireInRange("finished_fraction", finished_fraction, 0.0, 1.0);
}

void ObservableSurfaceConfig::validate() const {
  requireInRange("voxel_size_m", voxel_size_m, 0.01, 10.0);
  requireInRange("max_range_m", max_range_m, 0.1, 1000.0);
  requireInRange("rays_per_point", rays_per_point, 1, 10000000);
  requireInRange("clearance_m", clearance_m, 0.0, 10.0);
}

VoxelKeySet observableSurfaceKeys(const WorldGeometry& world,
                                  const std::vector<Eigen::Vector3d>& sample_points_world,
                                  const ObservableSurfaceConfig& config) {
  config.validate();
  // Fibonacci sphere: near-uniform directions without clustering at the poles.
  const int n = config.rays_per_point;
  std::vector<Eigen::Vector3f> dirs(n);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double a = golden * i;
    dirs[i] = Eigen::Vector3f(static_cast<float>(r * std::cos(a)),
                              static_cast<float>(r * std::sin(a)), static_cast<float>(z));
  }
  VoxelKeySet keys;
  std::vector<float> ranges;
  for (const Eigen::Vector3d& p : sample_points_world) {
    if (world.collides(p, config.clearance_m)) continue;
    world.castRays(p, dirs, config.max_range_m, &ranges);
    const Eigen::Vector3f o = p.cast<float>();
    for (int i = 0; i < n; ++i) {
      if (!std::isfinite(ranges[i])) continue;
      keys.insert(surfaceVoxelKey(o + ranges[i] * dirs[i], dirs[i], config.voxel_size_m));
    }
  }
  return keys;
}

std::vector<Eigen::Vector3d> freeSamplePoints(const WorldGeometry& world,
                                              const Eigen::AlignedBox3d& box_world,
                                              double spacing_m, double clearance_m) {
  requirePositive("spacing_m", spacing_m);
  requireInRange("clearance_m", clearance_m, 0.0, 100.0);
  std::vector<Eigen::Vector3d> out;
  for (double x = box_world.min().x() + 0.5 * spacing_m; x <= box_world.max().x(); x += spacing_m) {
    for (double y = box_world.min().y() + 0.5 * spacing_m; y <= box_world.max().y();
         y += spacing_m) {
      for (double z = box_world.min().z() + 0.5 * spacing_m; z <= box_world.max().z();
           z += spacing_m) {
        const Eigen::Vector3d p(x, y, z);
        if (!world.collides(p, clearance_m)) out.push_back(p);
      }
    }
  }
  return out;
}

Coverage::Coverage(const CoverageConfig& config, const VoxelKeySet& ground_truth_surface)
    : config_((config.validate(), config)), table_(ground_truth_surface) {
  seen_.assign(table_.size(), 0);
}

std::size_t Coverage::observe(const Eigen::Vector3d& sensor_origin_world,
                              const std::vector<Eigen::Vector3f>& surface_world,
                              const std::vector<Eigen::Vector3f>& dirs_world) {
  const Eigen::Vector3f o = sensor_origin_world.cast<float>();
  const float r2_max = static_cast<float>(config_.coverage_range_m * config_.coverage_range_m);
  std::size_t fresh = 0;
  VoxelKey last{INT32_MIN, INT32_MIN, INT32_MIN};
  const std::size_t n = std::min(surface_world.size(), dirs_world.size());
  for (std::size_t i = 0; i < n; ++i) {
    if ((surface_world[i] - o).squaredNorm() > r2_max) continue;
    const VoxelKey k = surfaceVoxelKey(surface_world[i], dirs_world[i], config_.voxel_size_m);
    if (k == last) continue;  // consecutive returns often share a voxel: skip the hash lookup
    last = k;
    const std::optional<size_t> index = table_.find(k);
    if (!index || seen_[*index]) continue;
    seen_[*index] = 1;
    ++seen_count_;
    ++fresh;
  }
  return fresh;
}

double Coverage::fraction() const {
  return table_.size() == 0 ? 0.0
                            : static_cast<double>(seen_count_) / static_cast<double>(table_.size());
}

bool Coverage::isSeen(const VoxelKey& k) const {
  const std::optional<size_t> index = table_.find(k);
  return index && seen_[*index];
}

SurfaceFacing surfaceFacing(const WorldGeometry& world, const VoxelKey& key, double voxel_size_m) {
  const Eigen::Vector3d c = voxelCenter(key, voxel_size_m);
  const Eigen::Vector3d up(0.0, 0.0, voxel_size_m);
  const bool solid_above = world.collides(c + up, 0.0);
  const bool solid_below = world.collides(c - up, 0.0);
  if (!solid_above && solid_below) return SurfaceFacing::kUp;
  if (solid_above && !solid_below) return SurfaceFacing::kDown;
  return SurfaceFacing::kSideways;
}

CoverageGaps coverageGaps(const Coverage& coverage, const WorldGeometry& world) {
  CoverageGaps g;
  g.voxel_size_m = coverage.config().voxel_size_m;
  std::vector<std::pair<VoxelKey, SurfaceFacing>> unseen;
  coverage.forEachVoxel([&](const VoxelKey& k, bool seen) {
    const SurfaceFacing facing = surfaceFacing(world, k, g.voxel_size_m);
    const bool up = facing == SurfaceFacing::kUp, down = facing == SurfaceFacing::kDown;
    (up ? g.total_up : down ? g.total_down : g.total_sideways)++;
    if (seen) return;
    (up ? g.up : down ? g.down : g.sideways)++;
    unseen.emplace_back(k, facing);
  });
  std::sort(unseen.begin(), unseen.end(),
            [](const auto& a, const auto& b) { return voxelKeyLess(a.first, b.first); });
  g.unseen.reserve(unseen.size());
  g.facing.reserve(unseen.size());
  for (const auto& [k, facing] : unseen) {
    g.unseen.push_back(k);
    g.facing.push_back(facing);
  }
  return g;
}

}  // namespace efs::sim
