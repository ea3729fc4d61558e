// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The observation map as the registration sees it: the 3D local map (world frame) sliced to a
// height band around the robot (floor and ceiling would otherwise hide every wall in the
// projection), projected onto the horizontal plane and thinned on a 2D grid.
#pragma once

#include <cstddef>

#include "sketch_registration/types.h"

namespace efs::registration {

struct ObservationConfig {
  double slice_min_dz_m = -1.0;  ///< band relative to the robot height
  double slice_max_dz_m = 1.0;
  double descriptor_voxel_m = 0.1;  ///< grid for the GeoContext input
  double icp_voxel_m = 0.3;         ///< grid for the Scale-ICP input
  double icp_range_m = 40.0;        ///< horizontal radius kept for Scale-ICP
  int icp_max_points = 800;         ///< evenly thinned above this
  void validate() const;
};

struct ProjectedMap {
  Points2d points_m;  ///< unique grid cells (cell centroids of the first point)
  size_t num_input = 0;
  size_t num_non_finite = 0;
  size_t num_in_band = 0;
};

/// Projects finite points with z in the band and horizontal distance <= range_m to the robot onto
/// a grid of `voxel_m`, one point per occupied cell (the first seen; deterministic).
ProjectedMap projectLocalMap(const Points3d& local_map_world_m,
                             const Eigen::Vector3d& robot_world_m, double min_dz_m, double max_dz_m,
                             double range_m, double voxel_m);

/// Keeps at most `max_points` with an even stride (deterministic).
Points2d thinEvenly(const Points2d& points, size_t max_points);

}  // namespace efs::registration
