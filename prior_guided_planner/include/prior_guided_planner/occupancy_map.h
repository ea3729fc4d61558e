// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Sparse occupancy of the explored space for the planner's collision checks, line-of-sight tests
// and path search. Cells live in hashed blocks of 8 x 8 x 8 (only blocks that a ray touched
// exist; the block index is a flat open-addressing table, since a block lookup is what every
// cell query costs), so memory grows with the explored volume, never with a bounding box: a 2 km
// cave fits. Each registered scan is ray cast from the sensor origin (Amanatides-Woo traversal):
// log-odds misses along the ray, a hit at the end point. Every cell is updated at most once per
// scan (a per-cell scan stamp), and hits win over misses within one scan, as in OctoMap.
// Inflation by the vehicle radius is a query (isSafe), not a stored layer, so it never has to be
// undone when a cell is cleared. Cell boundaries follow efs::toVoxelKey.
// The scan stamp is 8 bits: a cell left alone for exactly a multiple of 255 scans skips one
// update in the next scan that reaches it (harmless: one observation of many).
// Const queries may run concurrently; insertScan needs exclusive access.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <memory>
#include <vector>

#include "efs_common/voxel_key.h"
#include "efs_common/voxel_key_table.h"

namespace efs::planner {

/// Calls f(key) for each cell the segment a -> b passes through, from the cell of `a` up to but
/// excluding the cell of `b` (Amanatides-Woo). Stops early when f returns false; returns false
/// then. Exactly |dk|_1 cells are visited, so the walk ends even with rounding.
template <typename F>
bool forEachCellOnSegment(const Eigen::Vector3d& a_m, const Eigen::Vector3d& b_m,
                          double resolution_m, F&& f) {
  VoxelKey k = toVoxelKey(a_m, resolution_m);
  const VoxelKey kb = toVoxelKey(b_m, resolution_m);
  const Eigen::Vector3d d = b_m - a_m;
  int step[3];
  double t_max[3], t_delta[3];
  const int32_t ka[3] = {k.x, k.y, k.z};
  for (int i = 0; i < 3; ++i) {
    if (d[i] > 0.0) {
      step[i] = 1;
      t_max[i] = ((ka[i] + 1) * resolution_m - a_m[i]) / d[i];
      t_delta[i] = resolution_m / d[i];
    } else if (d[i] < 0.0) {
      step[i] = -1;
      t_max[i] = (ka[i] * resolution_m - a_m[i]) / d[i];
      t_delta[i] = -resolution_m / d[i];
    } else {
      step[i] = 0;
      t_max[i] = t_delta[i] = std::numeric_limits<double>::infinity();
    }
  }
  const int64_t n =
      std::abs(int64_t(kb.x) - k.x) + std::abs(int64_t(kb.y) - k.y) + std::abs(int64_t(kb.z) - k.z);
  int32_t* kk[3] = {&k.x, &k.y, &k.z};
  for (int64_t s = 0; s < n; ++s) {
    if (!f(static_cast<const VoxelKey&>(k))) return false;
    int axis = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
    // A zero step can only be picked by rounding at the very end of the walk; take another axis.
    if (step[axis] == 0) axis = step[0] ? 0 : (step[1] ? 1 : 2);
    *kk[axis] += step[axis];
    t_max[axis] += t_delta[axis];
  }
  return true;
}

struct OccupancyConfig {
  double resolution_m = 0.3;
  /// Points farther than this clear free space up to this range and leave no hit.
  double max_range_m = 40.0;
  /// Points closer than this are the vehicle itself and are ignored.
  double min_range_m = 0.3;
  double log_odds_hit = 0.85;
  double log_odds_miss = -0.4;
  /// A miss through a cell that is occupied now. Surface cells that a 0.3 m cell only partly
  /// fills are crossed by rays to the surface behind them: at the full miss some 100 cells per
  /// scan flipped between free and occupied in a mapped garage, and each flip invalidated the
  /// planner's cached path lengths nearby (the whole tour matrix searched again every scan).
  double log_odds_miss_occupied = -0.1;
  double log_odds_min = -2.0;
  double log_odds_max = 3.5;
  /// Known cells above this log-odds are occupied, the others free.
  double log_odds_occupied = 0.0;
  void validate() const;
};

enum class OccupancyState : uint8_t { kUnknown, kFree, kOccupied };

/// One cell whose state one scan changed.
struct CellChange {
  VoxelKey cell;
  OccupancyState before;
  OccupancyState after;
};

/// What one scan did; rejected points are counted, never silently dropped.
struct OccupancyUpdateStats {
  size_t points_in = 0;
  size_t points_rejected_nonfinite = 0;  ///< NaN / inf coordinates
  size_t points_rejected_too_close = 0;  ///< within min_range_m of the sensor
  size_t points_clipped = 0;             ///< beyond max_range_m: free space only
  size_t rays_cast = 0;                  ///< after merging rays ending in the same cell
  size_t cells_traversed = 0;
  size_t blocks_changed = 0;   ///< blocks in which some cell changed its state
  bool rejected_scan = false;  ///< non-finite sensor origin: nothing inserted
};

class OccupancyMap {
  struct Block;

 public:
  static constexpr int kBlockBits = 3;
  static constexpr int kBlockSize = 1 << kBlockBits;  ///< cells per block edge
  static constexpr int kBlockCells = kBlockSize * kBlockSize * kBlockSize;

  explicit OccupancyMap(OccupancyConfig config = {});

  const OccupancyConfig& config() const { return config_; }
  double resolution() const { return config_.resolution_m; }
  VoxelKey key(const Eigen::Vector3d& p_world_m) const {
    return toVoxelKey(p_world_m, config_.resolution_m);
  }
  Eigen::Vector3d center(const VoxelKey& k) const { return voxelCenter(k, config_.resolution_m); }
  static VoxelKey blockOf(const VoxelKey& cell) {
    return {cell.x >> kBlockBits, cell.y >> kBlockBits, cell.z >> kBlockBits};
  }

  /// Integrates one registered scan (world-frame points, world-frame sensor origin).
  OccupancyUpdateStats insertScan(const Eigen::Vector3d& sensor_origin_world_m,
                                  const std::vector<Eigen::Vector3d>& points_world_m);

  OccupancyState state(const VoxelKey& k) const;

  /// state() for many nearby cells: remembers the last block, so the cells of a ray, of a ball
  /// or around one cell mostly skip the block lookup. Valid while the map is not changed.
  class Cursor {
   public:
    explicit Cursor(const OccupancyMap& map) : map_(map) {}
    OccupancyState state(const VoxelKey& cell) { return map_.classify(value(cell)); }

   private:
    friend class OccupancyMap;
    // Inline: called per cell of rays, balls and whole-map passes.
    const Block* block(const VoxelKey& cell) {
      const VoxelKey bk = blockOf(cell);
      if (!valid_ || bk != key_) {
        key_ = bk;
        block_ = map_.findBlock(bk);
        valid_ = true;
      }
      return block_;
    }
    int8_t value(const VoxelKey& cell) {
      const Block* b = block(cell);
      return b ? b->cells[localIndex(cell)].log_odds : kUnknownValue;
    }
    const OccupancyMap& map_;
    VoxelKey key_;
    const Block* block_ = nullptr;
    bool valid_ = false;
  };
  OccupancyState stateAt(const Eigen::Vector3d& p_world_m) const { return state(key(p_world_m)); }
  bool isOccupied(const VoxelKey& k) const { return state(k) == OccupancyState::kOccupied; }
  bool isFree(const VoxelKey& k) const { return state(k) == OccupancyState::kFree; }
  bool isUnknown(const VoxelKey& k) const { return state(k) == OccupancyState::kUnknown; }

  /// True when the ball of `radius_m` around `p_world_m` touches no occupied cell and the cell
  /// at its centre is free (or unknown, when `unknown_is_safe`). This is the inflated query.
  bool isSafe(const Eigen::Vector3d& p_world_m, double radius_m, bool unknown_is_safe) const;
  /// Every cell the ball of `radius_m` around `p_world_m` touches is known free: no occupied
  /// and no unknown cell (a viewpoint next to a floor not seen yet is not safe).
  bool isKnownFree(const Eigen::Vector3d& p_world_m, double radius_m) const;
  /// isSafe at samples every half cell along the segment (end points included).
  bool segmentSafe(const Eigen::Vector3d& a_world_m, const Eigen::Vector3d& b_world_m,
                   double radius_m, bool unknown_is_safe) const;
  /// True when no occupied cell (and no unknown one, when `unknown_blocks`) lies on the voxel
  /// traversal from `from` to `to`, both end cells excluded: a sensor at `from` sees `to`.
  /// Cells within `ignore_near_to_cells` (Chebyshev, in cells) of the `to` cell are ignored too:
  /// a surface cell's own neighbours must not hide it.
  bool lineOfSight(const Eigen::Vector3d& from_world_m, const Eigen::Vector3d& to_world_m,
                   bool unknown_blocks, int ignore_near_to_cells = 0) const;

  /// Calls f(cell key, log-odds, state) for every known cell, block by block in the order the
  /// blocks were first touched (deterministic for a given sequence of scans).
  template <typename F>
  void forEachKnownCell(F&& f) const {
    for (size_t b = 0; b < blocks_.size(); ++b) {
      const VoxelKey& block_key = block_index_.key(b);
      const Block* block = blocks_[b].get();
      for (int i = 0; i < kBlockCells; ++i) {
        const int8_t v = block->cells[i].log_odds;
        if (v == kUnknownValue) continue;
        // Multiplication, not a shift: block keys are negative on one side of the origin.
        const VoxelKey cell{block_key.x * kBlockSize + (i & (kBlockSize - 1)),
                            block_key.y * kBlockSize + ((i >> kBlockBits) & (kBlockSize - 1)),
                            block_key.z * kBlockSize + (i >> (2 * kBlockBits))};
        f(cell, v * kQuantum, classify(v));
      }
    }
  }

  size_t numBlocks() const { return blocks_.size(); }
  size_t numKnownCells() const { return known_cells_; }
  /// Heap bytes of the block store (blocks + hash table), an estimate for benchmarks.
  size_t memoryBytes() const;
  /// Incremented by every insertScan that changed some cell's state.
  uint64_t revision() const { return revision_; }
  /// Blocks (block keys) in which a cell changed state during the last insertScan.
  const std::vector<VoxelKey>& lastChangedBlocks() const { return changed_blocks_; }
  /// The cells whose state the last insertScan changed, when there were at most
  /// kMaxListedChanges (a mapped place changes a few dozen per scan, its first scans thousands).
  /// Beyond that the list is empty and lastChangesListed() is false: use the blocks.
  static constexpr size_t kMaxListedChanges = 4096;
  const std::vector<CellChange>& lastChangedCells() const { return changed_cells_; }
  bool lastChangesListed() const { return changes_listed_; }
  /// Whether the last insertScan turned some unknown/occupied cell free, or some cell occupied.
  bool lastScanAddedFree() const { return last_added_free_; }
  bool lastScanAddedOccupied() const { return last_added_occupied_; }

 private:
  /// Every cell whose box meets the ball satisfies ok.
  bool allCellsInBall(const Eigen::Vector3d& p_world_m, double radius_m,
                      bool (*ok)(OccupancyState)) const;
  struct Cell {
    int8_t log_odds = kUnknownValue;
    uint8_t stamp = 0;
  };
  struct Block {
    Cell cells[kBlockCells];
    uint8_t changed_stamp = 0;
  };
  static constexpr int8_t kUnknownValue = -128;

  Block* findBlock(const VoxelKey& block_key) const;
  Block& touchBlock(const VoxelKey& block_key);
  static int localIndex(const VoxelKey& cell) {
    return (cell.x & (kBlockSize - 1)) | ((cell.y & (kBlockSize - 1)) << kBlockBits) |
           ((cell.z & (kBlockSize - 1)) << (2 * kBlockBits));
  }
  OccupancyState classify(int8_t v) const {
    if (v == kUnknownValue) return OccupancyState::kUnknown;
    return v > occupied_q_ ? OccupancyState::kOccupied : OccupancyState::kFree;
  }
  void updateCell(Block& b, const VoxelKey& block_key, const VoxelKey& cell, bool hit);

  OccupancyConfig config_;
  // Log-odds are stored as int8 in units of kQuantum to keep a block at 1 KiB.
  static constexpr double kQuantum = 0.05;
  int hit_q_, miss_q_, miss_occupied_q_, min_q_, max_q_, occupied_q_;
  VoxelKeyTable block_index_;                   ///< block key -> index into blocks_
  std::vector<std::unique_ptr<Block>> blocks_;  ///< by block_index_'s index
  uint8_t scan_stamp_ = 0;
  uint64_t revision_ = 0;
  size_t known_cells_ = 0;
  std::vector<VoxelKey> changed_blocks_;
  std::vector<CellChange> changed_cells_;
  bool changes_listed_ = true;
  bool last_added_free_ = false;
  bool last_added_occupied_ = false;
};

}  // namespace efs::planner
