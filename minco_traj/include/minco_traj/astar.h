// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Front end: A* on the local grid's inflated occupancy, 26-connected, step costs 1, sqrt2, sqrt3
// cells, with the 3D octile distance as heuristic (admissible and consistent for this
// neighbourhood, so the path is optimal on the grid). Bad requests get defined behaviour:
//   * goal outside the window -> clamped into it (if clamp_goal_to_window) then as below;
//   * goal blocked -> nearest traversable cell within goal_search_radius_m, else kGoalBlocked;
//   * start blocked (the robot is within its radius of an obstacle) -> the path first escapes to
//     the nearest traversable cell within start_escape_radius_m, else kStartInCollision.
// The grid path is then shortened by line-of-sight shortcuts on the same blocked test.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "minco_traj/local_grid.h"

namespace efs::traj {

struct AStarConfig {
  bool unknown_is_free = true;  ///< exploration plans optimistically through unknown space
  bool clamp_goal_to_window = true;
  double goal_search_radius_m = 1.0;
  double start_escape_radius_m = 0.6;
  int max_expansions = 400000;
  bool shortcut = true;
  /// 1 keeps A* optimal; > 1 (weighted A*) trades path length (at most this factor) for far
  /// fewer expansions in cluttered 3D space.
  double heuristic_weight = 1.0;
  /// > 0: cells count as blocked only within this distance of an occupied cell centre instead of
  /// the grid's inflation radius (LocalGrid::isBlocked): the narrow-passage search.
  double narrow_clearance_m = 0.0;
  /// A step into an unknown cell costs this many times its length (>= 1): the route keeps to
  /// space seen free where it can (shortcuts still cross unknown cells). Unknown space
  /// near the floor is where the Mid-360 (-7 to 52 deg, pitched down 15) does not look (seen: a
  /// path around an office desk dove to 0.35 m and hit it).
  double unknown_cost_factor = 1.0;
  /// With unknown_is_free: unknown cells are traversable only within this height of the goal's,
  /// the band widened to take in the start's own height; on the way down no lower than this
  /// below the start's height (the way down crosses seen space). The LiDAR looks neither
  /// straight down nor straight up (Mid-360: -7 to 52 deg, pitched), so a route that leaves that
  /// band through unknown space heads for a floor or ceiling nobody has seen (seen in ed21: a
  /// detour under a desk dove from 1.2 m to 0.35 m and hit the floor; one over a wall climbed to
  /// 2.25 m and hit the ceiling at 2.5 m). The goal's height, not the start's: a margin around
  /// the start moves with the vehicle, half a metre further each replan.
  double unknown_height_margin_m = 0.5;
  void validate() const;
};

enum class AStarStatus {
  kSuccess,
  kStartOutside,      ///< start not in the grid window
  kStartInCollision,  ///< start blocked and no free cell within start_escape_radius_m
  kGoalOutside,       ///< goal outside the window and clamping disabled
  kGoalBlocked,       ///< goal blocked and no free cell within goal_search_radius_m
  kNoPath,            ///< open set exhausted
  kExpansionLimit
};
const char* toString(AStarStatus s);

struct AStarResult {
  AStarStatus status = AStarStatus::kNoPath;
  bool goal_adjusted = false;  ///< the path ends at a substitute for the requested goal
  bool start_escaped = false;  ///< the path starts with an escape out of the inflated zone
  std::vector<Eigen::Vector3d> grid_path_world_m;  ///< cell centres (plus exact start/goal)
  std::vector<Eigen::Vector3d> path_world_m;       ///< shortened path
  double grid_path_length_m = 0.0;
  int expansions = 0;
  bool ok() const { return status == AStarStatus::kSuccess; }
};

/// Not thread-safe: plan() reuses per-cell scratch arrays sized to the grid window.
class AStarPlanner {
 public:
  explicit AStarPlanner(const AStarConfig& cfg = {});
  AStarResult plan(const LocalGrid& grid, const Eigen::Vector3d& start_world_m,
                   const Eigen::Vector3d& goal_world_m) const;
  /// True if no cell on the segment is blocked.
  /// Straight segment a -> b through traversable cells (unknown ones within the band of
  /// unknown_height_margin_m, from a's height up to b's).
  bool lineOfSight(const LocalGrid& grid, const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;
  /// Nearest traversable cell within radius_m (by centre distance), false if none.
  bool nearestFree(const LocalGrid& grid, const VoxelKey& k, double radius_m, VoxelKey* out) const;

 private:
  struct Band {
    double lo_z_m, hi_z_m;
  };
  Band unknownBand(double z0_m, double z1_m, double cell_m) const;
  bool traversable(const LocalGrid& grid, const VoxelKey& k, const Band& unknown_band) const;
  bool segmentClear(const LocalGrid& grid, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    const Band& unknown_band) const;
  bool nearestTraversable(const LocalGrid& grid, const VoxelKey& k, double radius_m,
                          const Band& unknown_band, VoxelKey* out) const;
  AStarConfig cfg_;
  mutable std::vector<uint32_t> stamp_;
  mutable std::vector<int32_t> node_of_;
  mutable uint32_t search_id_ = 0;
};

}  // namespace efs::traj
