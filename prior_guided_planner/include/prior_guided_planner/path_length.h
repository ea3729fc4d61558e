// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Searched path lengths L(a, b) between planner nodes (robot, viewpoints, guidepoints).
//  - A straight segment that is safe for the vehicle radius is its own path.
//  - Otherwise A* over a coarse lattice (`search_resolution_m`, 26-connected) whose nodes are
//    traversable when the ball of `vehicle_radius_m` around their centre is clear in the
//    occupancy (known free, unless unknown_is_traversable); the end points join the lattice by
//    collision-free segments. The found path is shortened greedily (string pulling) with the
//    same safety test, so open-space detours are not inflated by the lattice.
//  - Lattice edges are not checked between their two end balls: a path length estimate for
//    planning, not a collision-free trajectory (minco_traj builds that).
//  - Narrow passages: a 1 m door seen at 0.3 m occupancy has two or three free cells, and no
//    node of the 0.6 m lattice has the vehicle radius of clearance in it (seen: every method
//    stuck at 55-65 % of a generated office, rooms behind doors unreachable). A node without
//    that clearance is still traversable as a NARROW node when one of its 2^3 sub-points (the
//    centres of the occupancy cells it covers) is safe at `narrow_radius_m`; the node then
//    stands at that sub-point. Edges that touch a narrow node are checked (segment safe at
//    narrow_radius_m) and cost `narrow_cost_factor` times their length, so wide routes are
//    preferred and a narrow one is taken when it is the only way. Searches run over wide nodes
//    first and cross narrow ones only for what they did not reach, so open space pays nothing
//    for the shell of narrow nodes along its walls. minco_traj, at 0.1 m, decides whether the
//    vehicle really fits.
//  - No path: std::nullopt (never a large number). The expansion budget ending also gives
//    nullopt, with `budget_exhausted` set.
//  - Before any lattice search both ends' join nodes are labelled with their connected
//    component of the traversable lattice (a flood fill, once per component and occupancy
//    revision, not counted in the budget). Ends in different components are unreachable at
//    once (`expansions` 0): a failed search never explores the whole map.
//  - The lattice lives in sparse chunks of 8^3 nodes with flat arrays (traversability, component
//    label, search scratch), so memory follows the explored volume. Traversability is memoised
//    across occupancy revisions: when exactly one scan went by, only the nodes whose ball may
//    touch a changed occupancy block are tested again; otherwise the memo is dropped.
//  - searchFrom(): one Dijkstra from `a` for many targets (the robot to every viewpoint) with the
//    same rules; among equally long lattice paths it may pick another one than A*, so lengths
//    can differ from search() by what string pulling makes of that choice.
//  - PathLengthCache keys results by the two node ids (unordered pair) and the end positions.
//    After each OccupancyMap::insertScan call sync(): an entry is dropped when a changed block
//    lies within the vehicle radius plus one lattice step of its path (shortcuts that open
//    farther away are not noticed until the entry is dropped for another reason), and every
//    "unreachable" entry is dropped when the scan added free space (cheap to answer again: a
//    component label lookup). If several scans went by unseen, everything is dropped.
//    A miss from node a is answered together with the misses of a and the other nodes asked
//    within the last kBatchScans scans by one searchFrom(a) (from kMinBatch of them on), so a
//    new viewpoint costs one Dijkstra, not one A* per other viewpoint.
//  - Segment safety uses OccupancyMap::segmentSafe's samples, every 4th first (a segment
//    through a wall fails sooner; the answer is the same). searchFrom() remembers the answers
//    for the length of the call: its string pulling asks the same ones for many targets.
//  - Neither class is thread-safe (both memoise); the planner calls L from one thread.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "prior_guided_planner/occupancy_map.h"

namespace efs::planner {

struct PathSearchConfig {
  double search_resolution_m = 0.6;
  double vehicle_radius_m = 0.4;
  /// Clearance of a narrow node's sub-point (0 turns narrow nodes off; < vehicle_radius_m).
  double narrow_radius_m = 0.1;
  /// Edges touching a narrow node cost this many times their length (>= 1).
  double narrow_cost_factor = 1.5;
  bool unknown_is_traversable = false;
  int max_expansions = 200000;
  /// Cached results are reused while both end points moved less than this.
  double endpoint_tolerance_m = 0.05;
  bool shorten = true;
  /// String pulling looks at most this far ahead along the lattice path [m] for the farthest
  /// point a straight segment reaches. Unbounded, it tried every later node of every path: on a
  /// 495 m cave with 400 viewpoints one prior-free plan (lengths from the robot to each) took
  /// minutes, nearly all of it in segment checks hundreds of metres long.
  double shorten_lookahead_m = 20.0;
  void validate() const;
};

struct PathSearchResult {
  std::optional<double> length_m;
  std::vector<Eigen::Vector3d> waypoints_world_m;  ///< a ... b when found
  bool straight = false;
  bool budget_exhausted = false;
  int expansions = 0;
};

class PathSearch {
 public:
  PathSearch(const OccupancyMap& occ, PathSearchConfig config = {});
  ~PathSearch();
  PathSearch(const PathSearch&) = delete;
  PathSearch& operator=(const PathSearch&) = delete;
  const PathSearchConfig& config() const { return config_; }
  PathSearchResult search(const Eigen::Vector3d& a_world_m, const Eigen::Vector3d& b_world_m);
  /// Lengths from `a` to every target with one Dijkstra over the lattice (same rules as
  /// search(): straight when safe, else the lattice path shortened by string pulling; among
  /// equally long lattice paths it may pick another than A*). std::nullopt: no path, or the
  /// shared expansion budget ended. `expansions` (optional) receives the nodes expanded.
  /// Targets outside the components of `a`'s join nodes cost no expansion.
  std::vector<std::optional<double>> lengthsFrom(
      const Eigen::Vector3d& a_world_m, const std::vector<Eigen::Vector3d>& targets_world_m,
      int* expansions = nullptr);
  /// lengthsFrom() with the whole result (path, flags) per target.
  std::vector<PathSearchResult> searchFrom(const Eigen::Vector3d& a_world_m,
                                           const std::vector<Eigen::Vector3d>& targets_world_m);
  /// Whether a path may exist: the straight segment is safe, or some join node of `a` and
  /// some of `b` share a lattice component. False means search(a, b) finds nothing.
  bool connected(const Eigen::Vector3d& a_world_m, const Eigen::Vector3d& b_world_m);
  /// Forgets the lattice traversability memo and the component labels.
  void clearMemo();
  /// Call after each OccupancyMap::insertScan: forgets only the memo entries near the blocks
  /// the scan changed (everything when scans went by unseen), so that consecutive plans reuse
  /// the rest. PathLengthCache::sync calls it. Searches that find the occupancy changed
  /// without it drop the whole memo (correct, only slower).
  void syncWithLastScan();
  /// Lattice nodes whose traversability is memoised.
  size_t memoSize() const;

 private:
  struct Chunk;
  struct Slot {
    Chunk* chunk;
    int index;
  };
  using Joins = std::vector<std::pair<VoxelKey, double>>;

  Slot slot(const VoxelKey& k);
  /// f(chunk, index, key) for every node with a memoised test whose key lies in the box.
  template <typename F>
  void forEachMemoisedNode(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, F&& f);
  void syncWithChangedCells();
  bool traversable(const VoxelKey& k);
  bool traversable(const Slot& s, const VoxelKey& k);
  /// Where a traversable node stands: its centre, or a narrow node's safe sub-point.
  Eigen::Vector3d nodePosition(const Slot& s, const VoxelKey& k) const;
  /// Whether the edge between two traversable neighbours may be used (always between wide
  /// nodes; a safe segment when one is narrow), and what it costs (std::nullopt: unusable).
  std::optional<double> edgeCost(const Slot& sa, const VoxelKey& a, const Slot& sb,
                                 const VoxelKey& b, int direction) const;
  uint32_t component(const VoxelKey& k);
  Joins attach(const Eigen::Vector3d& p);
  /// The joins at wide (not narrow) nodes.
  Joins wideJoins(const Joins& joins);
  /// Segment tests answered during one searchFrom() call. The paths to its targets share
  /// their beginnings, and string pulling tested the same segments again for every target
  /// (about 30 % of a paper-size garage flight's CPU, with ~900 viewpoints). Valid only while
  /// the occupancy does not change, so it lives for one call.
  struct SegmentMemo;
  /// String pulling; `memo`, if given, answers segment tests asked before.
  std::vector<Eigen::Vector3d> shorten(std::vector<Eigen::Vector3d> path,
                                       SegmentMemo* memo = nullptr) const;
  bool segmentSafe(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_m,
                   bool unknown_is_safe) const;
  std::vector<Eigen::Vector3d> tracePath(const Eigen::Vector3d& a, const VoxelKey& last,
                                         const Eigen::Vector3d& b, SegmentMemo* memo = nullptr);
  struct SearchStats {
    int expansions = 0;
    bool exhausted = false;
  };
  template <typename Heuristic, typename Stop, typename Visit>
  SearchStats bestFirst(const Joins& starts, Heuristic&& h, Stop&& stop, Visit&& visit);
  Slot scratch(const VoxelKey& k);  ///< slot with this search's scratch initialised
  void ensureCurrent();
  Eigen::Vector3d center(const VoxelKey& k) const {
    return voxelCenter(k, config_.search_resolution_m);
  }

  const OccupancyMap& occ_;
  PathSearchConfig config_;
  std::unordered_map<VoxelKey, std::unique_ptr<Chunk>, VoxelKeyHash> chunks_;
  struct ChunkCacheLine {
    VoxelKey key;
    Chunk* chunk = nullptr;
  };
  std::array<ChunkCacheLine, 32> chunk_cache_{};
  uint64_t memo_revision_ = 0;
  uint32_t label_epoch_ = 1;  ///< component labels of older epochs are stale
  uint32_t next_label_ = 1;
  uint32_t search_epoch_ = 0;  ///< search scratch of older epochs is stale
  bool wide_only_ = false;     ///< the running search keeps off narrow nodes
};

struct PathCacheStats {
  size_t hits = 0;
  size_t misses = 0;
  size_t invalidated = 0;
  size_t batch_searches = 0;  ///< misses answered by one Dijkstra for a whole batch
};

class PathLengthCache {
 public:
  PathLengthCache(const OccupancyMap& occ, PathSearchConfig config = {});

  /// Misses from one node searched together (one Dijkstra) from this many on.
  static constexpr size_t kMinBatch = 4;
  /// Batches include the nodes asked within this many sync() calls (those of the current and
  /// the last planning cycles), not nodes the planner stopped asking about.
  static constexpr uint64_t kBatchScans = 4;

  /// L(a, b) for nodes with stable ids; searched once, then served from the cache. On a miss,
  /// when at least kMinBatch nodes asked recently (latest positions) also miss their entry
  /// with `a`, one Dijkstra from `a` fills all of them (PathSearch::searchFrom).
  std::optional<double> length(uint64_t id_a, const Eigen::Vector3d& a_world_m, uint64_t id_b,
                               const Eigen::Vector3d& b_world_m);
  /// The searched path of L(a, b), from a to b (searched as length() does on a miss); empty
  /// when b is unreachable from a.
  std::vector<Eigen::Vector3d> path(uint64_t id_a, const Eigen::Vector3d& a_world_m, uint64_t id_b,
                                    const Eigen::Vector3d& b_world_m);
  /// Invalidates what the occupancy's latest scan(s) may have changed.
  void sync();
  /// Forgets every entry that involves node `id` (a viewpoint that was dropped).
  void forget(uint64_t id);
  void clear() {
    entries_.clear();
    nodes_.clear();
  }
  size_t size() const { return entries_.size(); }
  const PathCacheStats& stats() const { return stats_; }
  PathSearch& search() { return search_; }

 private:
  struct Entry {
    Eigen::Vector3d a, b;
    std::optional<double> length_m;
    std::vector<Eigen::Vector3d> path_world_m;  ///< waypoints when found
    VoxelKey block_lo, block_hi;  ///< box of the path in occupancy blocks, grown by one
    VoxelKey cell_lo, cell_hi;    ///< box of the path in cells, grown by the reach of changes
  };
  struct PairHash {
    size_t operator()(const std::pair<uint64_t, uint64_t>& p) const noexcept {
      return std::hash<uint64_t>()(p.first * 0x9E3779B97F4A7C15ULL ^ p.second);
    }
  };

  const OccupancyMap& occ_;
  /// The entry of the pair when both ends are where it was searched, else nullptr.
  const Entry* valid(uint64_t id_a, const Eigen::Vector3d& a, uint64_t id_b,
                     const Eigen::Vector3d& b) const;
  /// Stores the result of a search from a to b.
  void store(uint64_t id_a, const Eigen::Vector3d& a, uint64_t id_b, const Eigen::Vector3d& b,
             PathSearchResult r);
  bool pathNear(const Entry& e, const std::vector<VoxelKey>& blocks) const;
  bool pathNear(const Entry& e, const std::vector<CellChange>& cells) const;

  PathSearch search_;
  std::unordered_map<std::pair<uint64_t, uint64_t>, Entry, PairHash> entries_;
  struct Node {
    Eigen::Vector3d position_world_m;
    uint64_t last_asked_scan = 0;  ///< value of scans_ when it was last asked
  };
  std::unordered_map<uint64_t, Node> nodes_;  ///< per node id, as last asked
  uint64_t scans_ = 0;                        ///< sync() calls
  uint64_t synced_revision_ = 0;
  PathCacheStats stats_;
};

}  // namespace efs::planner
