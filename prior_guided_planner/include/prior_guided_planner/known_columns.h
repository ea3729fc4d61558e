// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The horizontal columns of an occupancy map in which some cell, at any height, is known: where a
// scan has reached. Kept scan by scan like the opening cells (opening_cells.h): a cell never
// returns to unknown, so a column once seen stays seen and each scan only adds the columns of
// the cells it turned from unknown (listed by the map, or, past its list, found in the blocks it
// changed). The sketch's places are asked about on every plan once nothing else is left
// (unseenPlaces), and a pass over the whole map grows with the map: observation_map_bench, 150 /
// 400 m of cave, 2.0 / 3.6 ms median a pass against 0.09 ms a scan kept.
#pragma once

#include <cstdint>
#include <unordered_set>

#include "efs_common/voxel_key.h"
#include "prior_guided_planner/occupancy_map.h"

namespace efs::planner {

class KnownColumns {
 public:
  /// `occupancy` must outlive the index. Its columns known so far are taken by a whole pass.
  explicit KnownColumns(const OccupancyMap& occupancy);
  KnownColumns(const KnownColumns&) = delete;
  KnownColumns& operator=(const KnownColumns&) = delete;

  /// Call after each insertScan of the map.
  void update();
  /// Whether some cell of the column of cell keys (x, y) is known. A scan that update() did not
  /// see (the map's revision moved by more than one) makes it pass over the whole map first:
  /// slower, never wrong.
  bool seen(int x, int y);
  const OccupancyMap& map() const { return occ_; }
  size_t size() const { return columns_.size(); }
  /// Whole passes made (construction and any after a missed scan), for tests.
  int rebuilds() const { return rebuilds_; }

 private:
  void rebuild();
  void add(const VoxelKey& cell) { columns_.insert(cellKey2d(cell.x, cell.y)); }

  const OccupancyMap& occ_;
  std::unordered_set<long long> columns_;  ///< cellKey2d of the known columns
  uint64_t seen_revision_ = 0;
  int rebuilds_ = 0;
};

}  // namespace efs::planner
