// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The observation map (paper Sec. VI-A, after EPIC): the surface seen so far as cells of a
// spatial hash (efs::VoxelKey, 0.3 m by default), each either well or poorly observed.
//
// Rule (our reading of EPIC's "observed closely enough"):
//   a surface cell is WELL OBSERVED once
//     (a) some point fell in it from a sensor within `well_observed_distance_m`, or
//     (b) points fell in it from at least `min_view_directions` distinct viewing directions
//         (24 bins: 8 azimuth sectors x 3 elevation bands of the cell-to-sensor direction),
//         each from within `direction_rule_max_distance_m` (0 disables rule b), or
//     (c) a point fell in it from within `facing_max_distance_m` along a ray whose angle to
//         the surface normal has a cosine of at least `facing_min_cosine` (EPIC's "good
//         observation": seen from up to 12 m, not grazing). The normal is the least-variance
//         axis of the hit centroids of the cell and its surface neighbours (no normal, no
//         rule c, where fewer than 5 cells or no plane stand there);
//   otherwise it is POORLY OBSERVED. Being well observed is monotone: it is never lost.
// Without rule (c) a cave's ceiling and far wall, seen head-on from 6-10 m on the way past,
// stayed poorly observed: leftover viewpoints behind the robot kept guidepoints "exploring" and
// pulled the guided tour back (seen: a 500 m cave, the vehicle sent 60 m back at 130 s), and
// every method flew a long tail after the ground-truth coverage was complete.
// A FRONTIER cell is a poorly observed surface cell with at least one well observed cell among
// its 26 neighbours: the edge of the closely seen surface, where a closer look pays off.
// Both flags change monotonically with new observations, so one scan only touches the cells it
// hit and their neighbours; the changes are queued for the frontier clusterer.
// Memory is one hash entry per surface cell: it grows with the explored surface only.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "efs_common/voxel_key.h"

namespace efs::planner {

struct ObservationMapConfig {
  double resolution_m = 0.3;
  /// Points beyond this range (sensor max range) or closer than min_range_m are not surface.
  double max_range_m = 40.0;
  double min_range_m = 0.3;
  /// Rule (a): one observation from this close makes a cell well observed.
  double well_observed_distance_m = 5.0;
  /// Rule (b): this many distinct viewing directions (0 disables the rule) ...
  int min_view_directions = 3;
  /// ... each from within this distance.
  double direction_rule_max_distance_m = 10.0;
  /// Rule (c): one observation from within this distance (0 disables the rule) ...
  double facing_max_distance_m = 12.0;
  /// ... not grazing: |cos(ray, surface normal)| at least this (the ray at least 2.9 deg above
  /// the surface). At 0.6 a cave floor seen from mid-height was never well observed (the
  /// Mid-360 pitched 15 deg sees no lower than 22 deg below the horizon); at 0.3 a floor 1 m
  /// below still needed a pass within 3.2 m, and flights spent their tails on floor that already
  /// held returns (small garage: 60 % of the flight after 95 % coverage). With 0.05 a hit from
  /// within facing_max_distance_m marks a cell (EPIC's configurations trust observations within
  /// 12 m too); the angle only excludes rays skimming along the surface. Quick tier and its
  /// cost in the indoor world: README, "Well observed".
  double facing_min_cosine = 0.05;
  void validate() const;
};

struct SurfaceCell {
  Eigen::Vector3f hit_sum_m = Eigen::Vector3f::Zero();  ///< sum of the points that fell in it
  float min_distance_m = std::numeric_limits<float>::infinity();  ///< closest sensor so far
  uint32_t view_direction_bins = 0;  ///< bit i: seen from direction bin i (rule b range)
  uint32_t hits = 0;
  bool well_observed = false;
  bool frontier = false;
};

struct ObservationUpdateStats {
  size_t points_in = 0;
  size_t points_used = 0;
  size_t points_rejected_nonfinite = 0;
  size_t points_rejected_range = 0;
  size_t new_cells = 0;
  size_t newly_well_observed = 0;
  size_t frontier_changes = 0;
  bool rejected_scan = false;  ///< non-finite sensor origin
};

class ObservationMap {
 public:
  static constexpr int kNumDirectionBins = 24;

  explicit ObservationMap(ObservationMapConfig config = {});

  const ObservationMapConfig& config() const { return config_; }
  double resolution() const { return config_.resolution_m; }
  VoxelKey key(const Eigen::Vector3d& p_world_m) const {
    return toVoxelKey(p_world_m, config_.resolution_m);
  }
  Eigen::Vector3d center(const VoxelKey& k) const { return voxelCenter(k, config_.resolution_m); }

  ObservationUpdateStats insertScan(const Eigen::Vector3d& sensor_origin_world_m,
                                    const std::vector<Eigen::Vector3d>& points_world_m);

  /// nullptr when the cell is not (yet) surface.
  const SurfaceCell* cell(const VoxelKey& k) const;
  bool isWellObserved(const VoxelKey& k) const;
  bool isFrontier(const VoxelKey& k) const { return frontier_cells_.count(k) > 0; }

  size_t numSurfaceCells() const { return cells_.size(); }
  size_t numWellObserved() const { return num_well_; }
  size_t numFrontierCells() const { return frontier_cells_.size(); }
  const std::unordered_set<VoxelKey, VoxelKeyHash>& frontierCells() const {
    return frontier_cells_;
  }
  const std::unordered_map<VoxelKey, SurfaceCell, VoxelKeyHash>& cells() const { return cells_; }

  /// Cells whose frontier flag changed since the last call (deduplicated), then forgets them.
  std::vector<VoxelKey> takeFrontierChanges();

  /// Counts surface cells within `radius_m` of `p` (all / well observed); for guidepoint states.
  void countCellsNear(const Eigen::Vector3d& p_world_m, double radius_m, size_t* all,
                      size_t* well_observed) const;

  /// Best level in the vertical columns within `radius_m` (horizontal) of `center_xy`:
  /// 0 nothing seen, 1 poorly observed only, 2 some well observed cell. For guidepoint states,
  /// which live in the sketch's 2D plane.
  int bestLevelNear2d(const Eigen::Vector2d& center_xy_world_m, double radius_m) const;

  size_t memoryBytes() const;

  /// The rule in one place, exposed for tests and tuning.
  static bool isWellObservedRule(const ObservationMapConfig& c, double min_distance_m,
                                 uint32_t view_direction_bins);
  /// Bin of a (non-zero) direction from the cell towards the sensor.
  static int directionBin(const Eigen::Vector3d& cell_to_sensor);
  /// Unit surface normal at a cell (sign arbitrary) from the hit centroids of the cell and its
  /// surface neighbours; std::nullopt where they are too few (< 5) or form no plane.
  std::optional<Eigen::Vector3d> surfaceNormal(const VoxelKey& k) const;

 private:
  void setFrontier(const VoxelKey& k, SurfaceCell& c, bool frontier, ObservationUpdateStats& st);
  bool hasWellNeighbour(const VoxelKey& k) const;

  ObservationMapConfig config_;
  std::unordered_map<VoxelKey, SurfaceCell, VoxelKeyHash> cells_;
  std::unordered_set<VoxelKey, VoxelKeyHash> frontier_cells_;
  std::unordered_set<VoxelKey, VoxelKeyHash> frontier_changes_;
  /// Per vertical column (key with z = 0): best level of its cells (1 poor, 2 well).
  std::unordered_map<VoxelKey, uint8_t, VoxelKeyHash> columns_;
  size_t num_well_ = 0;
};

/// The 26 neighbour offsets of a cell.
const std::vector<VoxelKey>& neighbourOffsets26();

/// The 26-connected component of `pending` that holds `seed`, taken out of `pending` (seed
/// first). `seed` must be in `pending`.
std::vector<VoxelKey> takeComponent26(const VoxelKey& seed,
                                      std::unordered_set<VoxelKey, VoxelKeyHash>& pending);

}  // namespace efs::planner
