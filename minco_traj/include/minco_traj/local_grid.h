// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Local occupancy around the robot from registered scans (points already in the world frame).
// A dense ring buffer of `size_*_m` around a movable centre: cells keep their log-odds while the
// window slides. Free and unknown cells that leave it are forgotten; occupied ones are kept in a
// sparse surface memory (within memory_radius_m) and come back occupied when the window returns
// over them, so a passage flown back through is not planned through as unknown (seen: a cave
// floor hit at 3.6 m/s, the vehicle diving along a slope below the LiDAR's field of view into a
// floor it had mapped on the way in). Free space is cleared by ray casting from the
// sensor origin (Amanatides-Woo traversal), so unknown and free stay distinct. An inflation count
// per cell (how many occupied cells lie within `inflation_radius_m` of its centre) is maintained
// incrementally, so "blocked for a robot of this radius" is one lookup. Cell boundaries follow
// efs::toVoxelKey, shared with the rest of the suite.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "efs_common/voxel_key.h"

namespace efs::traj {

struct LocalGridConfig {
  double resolution_m = 0.1;
  double size_x_m = 24.0;  ///< window extent, centred on the robot
  double size_y_m = 24.0;
  double size_z_m = 6.0;
  double inflation_radius_m = 0.45;  ///< vehicle radius plus margin
  /// A second, smaller inflation kept for narrow-passage searches: isBlocked() with this
  /// clearance is one lookup (answered from the cells around otherwise; that search cost up to
  /// 87 % of a building mission's CPU when A* flooded a window in narrow mode). 0, or at least
  /// inflation_radius_m, keeps none.
  double narrow_radius_m = 0.36;
  double max_ray_length_m = 30.0;  ///< longer rays clear free space up to this range only
  /// Free space is cleared by one ray per end-point voxel of this size (0: a ray per point);
  /// every point still marks its hit. Rays are what a scan costs (memory-bound cell visits).
  double ray_downsample_m = 0.3;
  double logodds_hit = 0.85;
  double logodds_miss = -0.4;
  /// A miss through a cell that is occupied now. Rays that graze a floor or wall on their way to
  /// a farther point of it cross its cells; at the full miss they erased floors under the vehicle
  /// (seen: a collision with a cave floor the grid held free). Weaker, a surface survives them.
  double logodds_miss_occupied = -0.1;
  /// A hit makes the cell occupied at once, whatever misses it collected before: a floor far
  /// ahead is crossed by grazing rays long before it is hit itself. Right for the static worlds
  /// the planner explores; switch off for scenes with moving obstacles.
  bool hit_overrides_free = true;
  double logodds_min = -2.0;
  double logodds_max = 3.5;
  double logodds_occupied = 0.7;  ///< above this an observed cell is occupied
  /// Occupied cells that left the window, and hits above or below it, are remembered while
  /// within this horizontal distance of the window centre; 0 forgets them. The memory grows
  /// with the mapped surface (4 bytes per occupied cell).
  double memory_radius_m = 100.0;
  void validate() const;
};

enum class CellState : uint8_t { kUnknown, kFree, kOccupied, kOutside };
const char* toString(CellState s);

class LocalGrid {
 public:
  LocalGrid(const LocalGridConfig& cfg, const Eigen::Vector3d& center_world_m);

  const LocalGridConfig& config() const { return cfg_; }
  double resolution() const { return cfg_.resolution_m; }
  VoxelKey key(const Eigen::Vector3d& p_world_m) const {
    return toVoxelKey(p_world_m, cfg_.resolution_m);
  }
  Eigen::Vector3d center(const VoxelKey& k) const { return voxelCenter(k, cfg_.resolution_m); }
  /// Inclusive key range of the window.
  VoxelKey minKey() const { return min_key_; }
  VoxelKey maxKey() const {
    return {min_key_.x + nx_ - 1, min_key_.y + ny_ - 1, min_key_.z + nz_ - 1};
  }
  Eigen::Vector3d windowMin() const;  ///< lower corner of the window [m]
  Eigen::Vector3d windowMax() const;  ///< upper corner of the window [m]
  bool inWindow(const VoxelKey& k) const {
    return inWindowXY(k) && k.z >= min_key_.z && k.z < min_key_.z + nz_;
  }
  /// Inside the window's horizontal extent, at any height.
  bool inWindowXY(const VoxelKey& k) const {
    return k.x >= min_key_.x && k.x < min_key_.x + nx_ && k.y >= min_key_.y &&
           k.y < min_key_.y + ny_;
  }
  bool inWindow(const Eigen::Vector3d& p) const { return inWindow(key(p)); }

  /// Moves the window so that it is centred on `center_world_m`; forgotten cells become unknown.
  void recenter(const Eigen::Vector3d& center_world_m);
  /// Integrates one registered scan: misses along each ray, hits at the end points.
  void insertScan(const Eigen::Vector3d& sensor_origin_world_m,
                  const std::vector<Eigen::Vector3d>& points_world_m);
  /// Marks cells directly (tests, prior knowledge): occupied at maximum log-odds or free.
  void setOccupied(const Eigen::Vector3d& p_world_m);
  void setFree(const Eigen::Vector3d& p_world_m);
  /// Marks every cell of the window free (an empty, fully observed map).
  void setAllFree();

  CellState state(const VoxelKey& k) const;
  CellState state(const Eigen::Vector3d& p) const { return state(key(p)); }
  /// Within inflation_radius_m of an occupied cell (or occupied itself).
  bool isInflated(const VoxelKey& k) const;
  /// Not traversable: outside, inflated, or unknown when !unknown_is_free. With
  /// narrow_clearance_m > 0 an inflated cell is blocked only when an occupied cell centre lies
  /// within that (smaller) distance: the test of a narrow-passage search, answered from the
  /// cells around, since it is asked only when the inflated search found no way.
  bool isBlocked(const VoxelKey& k, bool unknown_is_free, double narrow_clearance_m = 0.0) const;

  /// Distance from p to the nearest occupied cell centre, if one lies within radius_m.
  std::optional<double> nearestOccupiedDistance(const Eigen::Vector3d& p_world_m,
                                                double radius_m) const;
  /// For each column of cells whose centres lie in [lo, hi] (x, y), the centre of the highest
  /// unobserved cell below top_z_m(x, y) (and at least lo.z): the top of what a LiDAR that does
  /// not look down has not seen beneath a path.
  void unobservedTopsBelow(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                           const std::function<double(double, double)>& top_z_m,
                           std::vector<Eigen::Vector3d>& out) const;
  /// Centres of occupied cells whose centres lie in [lo, hi]. With surface_only, cells whose six
  /// face neighbours are all occupied are left out (they cannot be nearer to free space than
  /// their neighbours by more than one cell).
  void occupiedCentersInBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                            std::vector<Eigen::Vector3d>& out, bool surface_only = false) const;
  /// Ring-buffer slot of an in-window key, in [0, cellCount()): for planners' scratch arrays.
  size_t slot(const VoxelKey& k) const { return index(k); }
  size_t cellCount() const { return cells_.size(); }
  size_t occupiedCount() const;
  /// Occupied cells remembered outside the window.
  size_t rememberedCount() const { return remembered_; }
  /// Heap bytes held: the window's cells and the surface memory (what memory_radius_m costs).
  size_t memoryBytes() const;

 private:
  // Inline: called per visited cell by ray casting, inflation stamping and A*.
  static int posMod(int a, int n) {
    const int r = a % n;
    return r < 0 ? r + n : r;
  }
  // Slot of an in-window key along one axis: key mod n without a division (a key lies in
  // [min, min + n), so its slot is the window's phase plus the offset, wrapped at most once).
  static int axisSlot(int k, int min_k, int phase, int n) {
    const int s = k - min_k + phase;
    return s >= n ? s - n : s;
  }
  size_t index(const VoxelKey& k) const {
    return (static_cast<size_t>(axisSlot(k.x, min_key_.x, phase_.x, nx_)) * ny_ +
            axisSlot(k.y, min_key_.y, phase_.y, ny_)) *
               nz_ +
           axisSlot(k.z, min_key_.z, phase_.z, nz_);
  }
  void setWindow(const VoxelKey& min_key);
  void updateCell(size_t idx, const VoxelKey& k, float delta);
  /// Per-axis flags over the slots (1: the slot's key entered the window with its last move).
  struct EnteringSlots {
    const uint8_t* x;
    const uint8_t* y;
    const uint8_t* z;
  };
  /// Adds (sign +1) or removes (-1) the occupied cell k's ball to the inflation counts; with
  /// `only`, to the cells of entering slots alone.
  void stampInflation(const VoxelKey& k, int sign, const EnteringSlots* only = nullptr);
  /// Visits (slot index, ix, iy, iz) of every slot flagged on at least one axis.
  template <typename Visit>
  void forEachChangingSlot(const std::vector<uint8_t>& ch_x, const std::vector<uint8_t>& ch_y,
                           const std::vector<uint8_t>& ch_z, Visit&& visit) const;
  bool isInterior(const VoxelKey& k) const;
  /// The block (kMemoryBlockBits cells a side) of the surface memory a cell belongs to.
  static VoxelKey memoryBlock(const VoxelKey& k) {
    return {k.x >> kMemoryBlockBits, k.y >> kMemoryBlockBits, k.z >> kMemoryBlockBits};
  }
  void remember(const VoxelKey& k, float logodds);
  /// A hit above or below the window (inside its horizontal extent) goes into the memory, to
  /// come back occupied when the window moves down or up over it: the floor of a descent is
  /// seen from above, more than size_z_m / 2 below, and the LiDAR does not see it again from
  /// right above it (seen: two collisions with cave floors the exploration map held occupied).
  /// Farther hits are not kept: the vehicle sees them again on its way there.
  void rememberHitAboveOrBelow(const VoxelKey& k, float logodds);
  /// The log-odds change of a hit on a cell holding `logodds` (hit_overrides_free).
  float hitDelta(float logodds) const;
  /// Brings remembered cells inside the window back into it (and out of the memory), with their
  /// inflation.
  void restoreRemembered();
  /// Drops memory blocks beyond memory_radius_m of the window centre.
  void cropMemory();
  /// Keys of the window's cells whose centres lie in [lo, hi] (empty when a max < its min).
  std::pair<VoxelKey, VoxelKey> keysInBox(const Eigen::Vector3d& lo,
                                          const Eigen::Vector3d& hi) const;

  LocalGridConfig cfg_;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  VoxelKey min_key_;
  /// Everything a ray step, an inflation stamp or a search step reads of one cell, together: a
  /// ray crosses cells a whole y-z plane apart, and one array per field cost a cache miss each.
  struct Cell {
    float logodds = 0.f;
    uint32_t scan_stamp = 0;
    uint16_t inflation = 0;         ///< occupied cells within inflation_radius_m
    uint16_t narrow_inflation = 0;  ///< the same within narrow_radius_m (if has_narrow_)
    uint8_t observed = 0;
    uint8_t occupied = 0;  ///< cached observed && logodds > threshold
  };
  std::vector<Cell> cells_;
  /// One bit per slot: the cell is free at logodds_min, where a miss changes nothing. A ray
  /// reads this (a few hundred kB, cache-resident) instead of the cell: in a mission profile
  /// half of insertScan was the cache miss on the cell of each step through space long cleared.
  std::vector<uint64_t> settled_free_;
  bool settledFree(size_t idx) const { return (settled_free_[idx >> 6] >> (idx & 63)) & 1u; }
  void setSettledFree(size_t idx, bool on) {
    const uint64_t bit = uint64_t{1} << (idx & 63);
    settled_free_[idx >> 6] = on ? settled_free_[idx >> 6] | bit : settled_free_[idx >> 6] & ~bit;
  }
  /// Whether cell c is one a miss leaves unchanged (the bit above).
  bool isSettledFree(const Cell& c) const {
    return c.observed && !c.occupied && c.logodds <= static_cast<float>(cfg_.logodds_min);
  }
  bool has_narrow_ = false;  ///< narrow_inflation is kept
  uint32_t scan_id_ = 0;
  VoxelKey phase_;  ///< slot of min_key_ along each axis (posMod(min_key_, n))
  /// The inflation ball as vertical runs: cells (dx, dy, dz) with |dz| <= half_height
  /// (narrow_half_height for the narrow ball, -1 where it has no cell in that column).
  struct KernelColumn {
    int dx, dy, half_height, narrow_half_height;
  };
  std::vector<KernelColumn> kernel_;
  int kernel_reach_ = 0;  ///< largest |offset| of the ball along an axis [cells]
  /// Scratch of stampInflation: per-axis slot of k + offset, or -1 outside the window.
  std::vector<int> stamp_slots_x_, stamp_slots_y_, stamp_slots_z_;
  std::vector<std::pair<uint64_t, uint32_t>> ray_bins_;  ///< scratch: (coarse key, point index)

  /// Four bytes: the cell's offset in its block and its log-odds quantised over
  /// [logodds_min, logodds_max], rounded up so that a remembered cell stays above the occupied
  /// threshold. A 500 m cave's surface memory was 68 MB as a full key and a float per cell.
  struct RememberedCell {
    uint8_t x, y, z;
    uint8_t logodds_q;
  };
  RememberedCell packRemembered(const VoxelKey& k, const VoxelKey& block, float logodds) const;
  VoxelKey rememberedKey(const RememberedCell& c, const VoxelKey& block) const;
  float rememberedLogodds(const RememberedCell& c) const;
  static constexpr int kMemoryBlockBits = 4;
  static constexpr int kMemoryBlockSide = 1 << kMemoryBlockBits;
  /// Log-odds per quantisation step of a remembered cell.
  double rememberedLogoddsStep() const { return (cfg_.logodds_max - cfg_.logodds_min) / 255.0; }
  std::unordered_map<VoxelKey, std::vector<RememberedCell>, VoxelKeyHash> memory_;
  size_t remembered_ = 0;
};

/// Visits the cells a segment passes through (Amanatides-Woo), from the start cell to the end
/// cell inclusive; `visit(key)` returns false to stop early. Returns false if stopped.
template <typename Visit>
bool traverseCells(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double res,
                   Visit&& visit);

}  // namespace efs::traj

#include "minco_traj/impl/traverse_cells.h"
