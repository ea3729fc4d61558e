// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Ground-truth coverage: the fraction of the world's observable surface voxels (0.3 m by
// default, the paper's map resolution) that received at least one LiDAR return within range.
// The set of observable surface voxels comes from the world itself (a voxel world knows its
// surface) or from observableSurfaceKeys(), which samples any WorldGeometry by casting dense ray
// bundles from free-space points. The paper counts a run finished at 95 % coverage.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "efs_common/voxel_key.h"
#include "efs_common/voxel_key_table.h"
#include "marsim_worlds/world_geometry.h"

namespace efs::sim {

using VoxelKeySet = std::unordered_set<VoxelKey, VoxelKeyHash>;

struct CoverageConfig {
  double voxel_size_m = 0.3;
  /// Returns farther than this from the sensor do not count (the LiDAR's own max range also
  /// applies). The paper's coverage counts what was seen within the mapping range.
  double coverage_range_m = 40.0;
  double finished_fraction = 0.95;

  void validate() const;  ///< Throws efs::ConfigError naming the key.
};

/// The voxel a return belongs to: the hit point pushed a millimetre along the ray, so that a hit
/// exactly on a voxel boundary (an axis-aligned wall) lands in the voxel behind the surface,
/// the same one for every ray. Ground truth and coverage both use it. A world that supplies its
/// own ground truth should therefore give the keys of its occupied cells that touch free space
/// (efs::toVoxelKey of their centres, on the global 0.3 m grid anchored at the origin).
inline VoxelKey surfaceVoxelKey(const Eigen::Vector3f& hit_world, const Eigen::Vector3f& dir_unit,
                                double voxel_size_m) {
  const Eigen::Vector3f p = hit_world + 1e-3f * dir_unit;
  return toVoxelKey(p.cast<double>(), voxel_size_m);
}

struct ObservableSurfaceConfig {
  double voxel_size_m = 0.3;
  double max_range_m = 40.0;
  int rays_per_point = 20000;  ///< Fibonacci-sphere bundle cast from each sample point.
  /// Sample points closer than this to the world (WorldGeometry::collides) are skipped.
  double clearance_m = 0.3;

  void validate() const;  ///< Throws efs::ConfigError naming the key.
};

/// Surface voxels seen from any of `sample_points_world` by a full-sphere bundle of rays.
VoxelKeySet observableSurfaceKeys(const WorldGeometry& world,
                                  const std::vector<Eigen::Vector3d>& sample_points_world,
                                  const ObservableSurfaceConfig& config);

/// Free-space sample points on a grid of `spacing_m` inside `box_world` that keep `clearance_m`
/// from the world (for observableSurfaceKeys).
std::vector<Eigen::Vector3d> freeSamplePoints(const WorldGeometry& world,
                                              const Eigen::AlignedBox3d& box_world,
                                              double spacing_m, double clearance_m);

class Coverage {
 public:
  Coverage(const CoverageConfig& config, const VoxelKeySet& ground_truth_surface);

  const CoverageConfig& config() const { return config_; }

  /// Marks the voxels of `surface_world` (noise-free returns; directions `dirs_world` as in
  /// surfaceVoxelKey) seen from `sensor_origin_world`. Returns the number of newly seen voxels.
  std::size_t observe(const Eigen::Vector3d& sensor_origin_world,
                      const std::vector<Eigen::Vector3f>& surface_world,
                      const std::vector<Eigen::Vector3f>& dirs_world);

  std::size_t totalVoxels() const { return table_.size(); }
  std::size_t seenVoxels() const { return seen_count_; }
  /// Seen / total; 0 for an empty ground truth.
  double fraction() const;
  bool finished() const { return fraction() >= config_.finished_fraction; }
  bool isSeen(const VoxelKey& k) const;
  /// Calls f(key, seen) for every ground-truth surface voxel, in no particular order.
  template <class F>
  void forEachVoxel(F&& f) const {
    for (std::size_t i = 0; i < table_.size(); ++i) f(table_.key(i), seen_[i] != 0);
  }

 private:
  CoverageConfig config_;
  VoxelKeyTable table_;
  std::vector<uint8_t> seen_;  ///< per surface voxel, by its index in table_
  std::size_t seen_count_ = 0;
};

/// Which way a ground-truth surface voxel faces, judged from the world one voxel above and below
/// its centre: up (free above, solid below: floors, car roofs), down (solid above, free below:
/// ceilings), otherwise sideways (walls, and edges where neither holds).
enum class SurfaceFacing { kUp, kDown, kSideways };
SurfaceFacing surfaceFacing(const WorldGeometry& world, const VoxelKey& key, double voxel_size_m);

/// Where coverage fell short: the unseen ground-truth surface, by the way it faces, beside the
/// whole surface so counted. On the paper-size garage the floor is what is missed most (README,
/// "Where coverage falls short").
struct CoverageGaps {
  std::vector<VoxelKey> unseen;                                  ///< voxelKeyLess order
  std::vector<SurfaceFacing> facing;                             ///< per unseen voxel
  std::size_t up = 0, down = 0, sideways = 0;                    ///< unseen
  std::size_t total_up = 0, total_down = 0, total_sideways = 0;  ///< the whole ground truth
  double voxel_size_m = 0.0;                                     ///< of the keys
};
CoverageGaps coverageGaps(const Coverage& coverage, const WorldGeometry& world);

}  // namespace efs::sim
