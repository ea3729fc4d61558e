// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/known_columns.h"

namespace efs::planner {

KnownColumns::KnownColumns(const OccupancyMap& occupancy) : occ_(occupancy) { rebuild(); }

void KnownColumns::rebuild() {
  columns_.clear();
  occ_.forEachKnownCell([&](const VoxelKey& k, double, OccupancyState) { add(k); });
  seen_revision_ = occ_.revision();
  ++rebuilds_;
}

void KnownColumns::update() {
  const uint64_t revision = occ_.revision();
  if (revision == seen_revision_) return;  // the scan changed no cell's state
  if (revision != seen_revision_ + 1) {
    rebuild();
    return;
  }
  seen_revision_ = revision;
  if (occ_.lastChangesListed()) {
    for (const CellChange& c : occ_.lastChangedCells())
      if (c.before == OccupancyState::kUnknown) add(c.cell);
    return;
  }
  OccupancyMap::Cursor cur(occ_);
  const int n = OccupancyMap::kBlockSize;
  for (const VoxelKey& b : occ_.lastChangedBlocks())
    for (int z = b.z * n; z < (b.z + 1) * n; ++z)
      for (int y = b.y * n; y < (b.y + 1) * n; ++y)
        for (int x = b.x * n; x < (b.x + 1) * n; ++x)
          if (cur.state({x, y, z}) != OccupancyState::kUnknown) add({x, y, z});
}

bool KnownColumns::seen(int x, int y) {
  if (occ_.revision() != seen_revision_) rebuild();  // scans went by without update()
  return columns_.count(cellKey2d(x, y)) > 0;
}

}  // namespace efs::planner
