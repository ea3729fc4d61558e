// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/opening_cells.h"

#include <utility>

namespace efs::planner {

namespace {

constexpr int kHorizontal[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
/// Opening cells keep this many cells above a floor (0.6 m at 0.3 m) and one below a ceiling.
constexpr int kFloorCells = 2;
constexpr int kCeilingCells = 1;
/// Past this many cells in marked blocks the marks are dropped for one pass over the map when
/// openings are next asked for: they would otherwise grow while nobody asks.
constexpr size_t kMaxDirtyCells = size_t{1} << 20;
/// Cells one changed block can affect: the block grown by the neighbourhood below.
constexpr size_t kCellsPerDirtyBlock = (OccupancyMap::kBlockSize + 2) *
                                       (OccupancyMap::kBlockSize + 2) *
                                       (OccupancyMap::kBlockSize + kFloorCells + kCeilingCells);

bool inBounds(const std::optional<Eigen::AlignedBox3d>& bounds, const Eigen::Vector3d& p) {
  return !bounds || bounds->contains(p);
}

/// The cell's direction to its unknown neighbours when it is an opening cell.
std::optional<Eigen::Vector2d> openingDirection(const OccupancyMap& occ, OccupancyMap::Cursor& cur,
                                                const VoxelKey& k, OccupancyState s,
                                                const std::optional<Eigen::AlignedBox3d>& bounds) {
  if (s != OccupancyState::kFree) return std::nullopt;
  // Not hugging a floor or a ceiling: what lies under a desk or in a roof pocket is no way on,
  // and down there the Mid-360 does not see the floor ahead.
  for (int dz = -kFloorCells; dz <= kCeilingCells; ++dz)
    if (dz != 0 && cur.state({k.x, k.y, k.z + dz}) == OccupancyState::kOccupied)
      return std::nullopt;
  if (!inBounds(bounds, occ.center(k))) return std::nullopt;
  Eigen::Vector2d dir = Eigen::Vector2d::Zero();
  int unknown = 0;
  for (const auto& d : kHorizontal) {
    const VoxelKey n{k.x + d[0], k.y + d[1], k.z};
    // The box's own edge is not a way on.
    if (cur.state(n) == OccupancyState::kUnknown && inBounds(bounds, occ.center(n))) {
      dir += Eigen::Vector2d(d[0], d[1]);
      ++unknown;
    }
  }
  if (unknown == 0) return std::nullopt;
  return dir;
}

/// Calls f(cell) for every cell whose status the change can alter: the cell itself; its
/// horizontal neighbours when it became or stopped being unknown (their unknown neighbour); the
/// cells up to two above and one below it when it became or stopped being occupied (their
/// floor or ceiling).
template <typename F>
void forEachAffected(const CellChange& change, F&& f) {
  const VoxelKey& c = change.cell;
  f(c);
  const auto was_or_is = [&](OccupancyState s) { return change.before == s || change.after == s; };
  if (was_or_is(OccupancyState::kOccupied))
    for (int dz = -kCeilingCells; dz <= kFloorCells; ++dz)
      if (dz != 0) f({c.x, c.y, c.z + dz});
  if (was_or_is(OccupancyState::kUnknown))
    for (const auto& d : kHorizontal) f({c.x + d[0], c.y + d[1], c.z});
}

}  // namespace

OpeningCells openingCellsOf(const OccupancyMap& occ,
                            const std::optional<Eigen::AlignedBox3d>& bounds) {
  OpeningCells cells;
  OccupancyMap::Cursor cur(occ);  // the neighbours mostly share the cell's block
  occ.forEachKnownCell([&](const VoxelKey& k, double, OccupancyState s) {
    if (const auto dir = openingDirection(occ, cur, k, s, bounds)) cells.emplace(k, *dir);
  });
  return cells;
}

OpeningCellIndex::OpeningCellIndex(const OccupancyMap& occupancy,
                                   std::optional<Eigen::AlignedBox3d> bounds_world_m)
    : occ_(occupancy), bounds_(std::move(bounds_world_m)), seen_revision_(occupancy.revision()) {}

void OpeningCellIndex::update() {
  const uint64_t revision = occ_.revision();
  if (revision == seen_revision_) return;  // the scan changed no cell's state
  const bool one_scan = revision == seen_revision_ + 1;
  seen_revision_ = revision;
  if (rebuild_) return;
  if (!one_scan) {
    rebuild_ = true;
  } else if (occ_.lastChangesListed()) {
    OccupancyMap::Cursor cur(occ_);
    for (const CellChange& c : occ_.lastChangedCells())
      forEachAffected(c, [&](const VoxelKey& k) { refresh(k, cur); });
  } else {
    for (const VoxelKey& b : occ_.lastChangedBlocks()) dirty_blocks_.insert(b);
  }
  if (dirty_blocks_.size() * kCellsPerDirtyBlock > kMaxDirtyCells) rebuild_ = true;
  if (rebuild_) dirty_blocks_.clear();
}

void OpeningCellIndex::refresh(const VoxelKey& k, OccupancyMap::Cursor& cur) {
  if (const auto dir = openingDirection(occ_, cur, k, cur.state(k), bounds_))
    cells_[k] = *dir;
  else
    cells_.erase(k);
}

const OpeningCells& OpeningCellIndex::cells() {
  if (occ_.revision() != seen_revision_) {
    // Scans went by without update(): their changes are not known.
    seen_revision_ = occ_.revision();
    rebuild_ = true;
  }
  if (rebuild_ || dirty_blocks_.size() * kCellsPerDirtyBlock > occ_.numKnownCells()) {
    cells_ = openingCellsOf(occ_, bounds_);
    ++rebuilds_;
    rebuild_ = false;
  } else {
    OccupancyMap::Cursor cur(occ_);
    for (const VoxelKey& b : dirty_blocks_) {
      const int n = OccupancyMap::kBlockSize;
      const VoxelKey lo{b.x * n, b.y * n, b.z * n};
      for (int z = lo.z - kCeilingCells; z < lo.z + n + kFloorCells; ++z)
        for (int y = lo.y - 1; y <= lo.y + n; ++y)
          for (int x = lo.x - 1; x <= lo.x + n; ++x) refresh({x, y, z}, cur);
    }
  }
  dirty_blocks_.clear();
  return cells_;
}

}  // namespace efs::planner
