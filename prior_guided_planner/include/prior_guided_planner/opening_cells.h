// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The cells openings are made of (openings.h): known free cells, not within two cells above a
// floor or right below a ceiling, with an unknown horizontal neighbour inside the exploration
// box. Openings are in every tour from a flight's first plan (OpeningTourMembership), so they
// are asked for at every plan, and a pass over the whole map costs what the map holds (10 % of
// the paper-size garage's samples at 230 s). OpeningCellIndex keeps the set scan by scan
// instead, re-examining only the cells a scan's changes can affect: per plan it costs 0.7 of
// the pass on a 150 m cave and half at 400 m, and stays flat as the map grows
// (observation_map_bench).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "prior_guided_planner/occupancy_map.h"

namespace efs::planner {

/// Opening cells, each with the summed direction (cells) to its unknown horizontal neighbours.
using OpeningCells = std::unordered_map<VoxelKey, Eigen::Vector2d, VoxelKeyHash>;

/// Every opening cell of `occupancy`, by a pass over its known cells.
OpeningCells openingCellsOf(const OccupancyMap& occupancy,
                            const std::optional<Eigen::AlignedBox3d>& bounds_world_m);

/// openingCellsOf(), kept up to date by update() after every OccupancyMap::insertScan: the cells
/// a scan changed are listed by the map (up to OccupancyMap::kMaxListedChanges), and the cells
/// whose status they can change are looked at again at once (the cell; its horizontal
/// neighbours if it became or stopped being unknown; two above and one below if it became or
/// stopped being occupied); past that (a first scan of a new place) the changed blocks are
/// marked and looked at again, grown by that neighbourhood, when cells() is asked for. A scan
/// that update() did not see (the map's revision moved by more than one) makes cells() rebuild
/// the set by a whole pass: slower, never wrong.
class OpeningCellIndex {
 public:
  /// `occupancy` must outlive the index.
  OpeningCellIndex(const OccupancyMap& occupancy,
                   std::optional<Eigen::AlignedBox3d> bounds_world_m);
  OpeningCellIndex(const OpeningCellIndex&) = delete;
  OpeningCellIndex& operator=(const OpeningCellIndex&) = delete;

  /// Call after each insertScan of the map.
  void update();
  /// The opening cells of the map as it is now.
  const OpeningCells& cells();
  const std::optional<Eigen::AlignedBox3d>& bounds() const { return bounds_; }
  /// Whole passes made (the first cells() and any after a missed scan), for tests.
  int rebuilds() const { return rebuilds_; }

 private:
  void refresh(const VoxelKey& cell, OccupancyMap::Cursor& cursor);

  const OccupancyMap& occ_;
  std::optional<Eigen::AlignedBox3d> bounds_;
  OpeningCells cells_;
  uint64_t seen_revision_ = 0;
  bool rebuild_ = true;
  std::unordered_set<VoxelKey, VoxelKeyHash> dirty_blocks_;
  int rebuilds_ = 0;
};

}  // namespace efs::planner
