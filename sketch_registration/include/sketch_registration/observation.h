// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The observation map as the registration sees it: what a person would draw of the 3D local map
// (world frame), as 2D points. The paper (Sec. V-C) projects the whole observation map onto the
// plane and keeps its boundary; a plain projection would be all floor and ceiling, and a thin
// height slice around the robot puts a cave's walls ~1 m inside the drawn outline (the widest
// extent of the passage) and keeps parked cars the drawing omits.
//
// Wall columns: the points of a generous height band around the robot are binned into vertical
// columns of `column_cell_m`. Within a column, a vertical gap larger than `wall_max_gap_m` is free
// space between a lower and an upper surface (floor and ceiling, car roof and ceiling, floor and
// lintel): the column is passage. A column whose points form one vertical run (no such gap) at
// least `wall_min_height_m` tall is wall (unless it is a low obstacle, below); shorter runs (a
// patch of floor or ceiling) are neither. In a cave the outermost column of a bulging
// wall holds the tangent part of the wall, a tall run, while the columns inside it see the wall's
// lower and upper slopes with free space between them: the outline a person draws. Doors are gaps
// (floor + lintel); car columns have space above the roof and are passage.
//
// Low obstacles: a car side seen from afar, with no ceiling return in its own column, is one run
// from the floor to the roof, as tall as a wall. What tells it from a wall is its top: there is
// open space above it, and nothing continues it upward. Open space above a top means either that
// the top is seen below `wall_top_clear_m` above the robot (well inside the LiDAR's vertical field
// of view, so a taller wall would have been seen taller), or that it lies more than
// `wall_max_gap_m` below the highest point seen within 1-2 m (the ceiling beside a car; the robot
// flies anywhere from 0.7 to 2.7 m in a garage, below car roofs too). A wall either reaches up
// there (a building's walls meet the ceiling) or, where its column's run ends lower (the
// outermost column of a cave wall that curves over), continues upward in a neighbouring column.
// A run with open space above it that does neither is a low obstacle the drawing leaves out
// (parked cars, crates) and is not wall. A wall the LiDAR saw only up to its column's top cannot
// end below `wall_top_clear_m` above the robot unless it is closer than
// wall_top_clear_m / tan(52 deg) ~ 0.25 m (the Mid-360's upper field of view).
//
// One code path: the descriptor and Scale-ICP both use observeLocalMap's points (ICP a coarser
// grid of them over a wider range).
#pragma once

#include <cstddef>

#include "sketch_registration/types.h"

namespace efs::registration {

struct ObservationConfig {
  /// true: wall columns (see above); false: every occupied column of the band (a height slice).
  bool wall_columns = true;
  double slice_min_dz_m = -3.0;    ///< band relative to the robot height
  double slice_max_dz_m = 4.0;     ///< band relative to the robot height
  double column_cell_m = 0.25;     ///< column grid (and the descriptor's input grid)
  double wall_min_height_m = 1.2;  ///< a wall column's points span at least this vertically
  double wall_max_gap_m = 1.2;     ///< a larger vertical gap in a column = free space (passage)
  /// A wall run whose top is lower than this above the robot has open space above it.
  double wall_top_clear_m = 0.3;
  /// A run with open space above it (the line above, or wall_max_gap_m below the highest point
  /// seen within 1-2 m) is wall only if one of its 8 neighbouring columns holds a point between
  /// kContinuationMinDz and this far above its top (the surface continues upward); otherwise it
  /// is a low obstacle. 0: every run tall enough is wall (no low-obstacle test).
  double wall_continuation_m = 0.6;
  double icp_voxel_m = 0.3;   ///< grid for the Scale-ICP input
  double icp_range_m = 40.0;  ///< horizontal radius kept for Scale-ICP
  int icp_max_points = 800;   ///< evenly thinned above this
  void validate() const;
};

struct ProjectedMap {
  Points2d points_m;  ///< one point per kept column: the mean position of its points
  /// The passage columns' mean positions (ObservationHistory forgets remembered walls there).
  Points2d passage_m;
  /// The other columns' mean positions (too short a run for a wall: floor or ceiling patches).
  /// With points_m and passage_m: everything the local map has seen in the band.
  Points2d other_m;
  size_t num_input = 0;
  size_t num_non_finite = 0;
  size_t num_in_band = 0;
  size_t num_columns = 0;  ///< occupied columns in the band within range
  size_t num_passage_columns = 0;
  /// Runs tall enough for a wall, rejected as low obstacles (counted into other_m).
  size_t num_low_obstacle_columns = 0;
};

/// A neighbour's point must lie this far above a run's top to continue it: above the ranging
/// noise (2 cm) at a flat top such as a car roof, below the rise of any surface steeper than
/// ~20 deg over one column.
constexpr double kContinuationMinDz = 0.1;

/// The observation: the columns (see the file comment) of finite points with z in the band and
/// horizontal distance <= range_m to the robot, one point per kept column, in a deterministic
/// order.
ProjectedMap observeLocalMap(const Points3d& local_map_world_m,
                             const Eigen::Vector3d& robot_world_m, const ObservationConfig& config,
                             double range_m);

/// The points within `range_m` of `centre_m`, one per `voxel_m` grid cell (the first seen).
Points2d thinToGrid(const Points2d& points, const Eigen::Vector2d& centre_m, double range_m,
                    double voxel_m);

/// Keeps at most `max_points` with an even stride (deterministic).
Points2d thinEvenly(const Points2d& points, size_t max_points);

/// Key of the `cell_m` grid cell holding `p` (one key space for every 2D grid of the module).
long long gridCellKey(const Eigen::Vector2d& p, double cell_m);

/// What one frame hands to the descriptor and to Scale-ICP, all from one observeLocalMap call.
struct Observation {
  ProjectedMap map;       ///< over max(descriptor_range_m, icp_range_m)
  Points2d descriptor_m;  ///< within descriptor_range_m, on the column grid
  Points2d icp_dense_m;   ///< within icp_range_m, on the icp_voxel_m grid (reverse fitness term)
  Points2d icp_m;         ///< icp_dense_m thinned to icp_max_points (ICP iterations)
  Points2d passage_m;     ///< map.passage_m within icp_range_m
};
Observation observe(const Points3d& local_map_world_m, const Eigen::Vector3d& robot_world_m,
                    const ObservationConfig& config, double descriptor_range_m);

}  // namespace efs::registration
