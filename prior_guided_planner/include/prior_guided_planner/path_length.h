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
//  - No path: std::nullopt (never a large number). The expansion budget ending also gives
//    nullopt, with `budget_exhausted` set.
//  - PathLengthCache keys results by the two node ids (unordered pair) and the end positions.
//    After each OccupancyMap::insertScan call sync(): an entry is dropped when a block changed
//    inside its path's box (plus one block), and every "unreachable" entry is dropped when the
//    scan added free space. If several scans went by unseen, everything is dropped.
//  - Neither class is thread-safe (both memoise); the planner calls L from one thread.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "prior_guided_planner/occupancy_map.h"

namespace efs::planner {

struct PathSearchConfig {
  double search_resolution_m = 0.6;
  double vehicle_radius_m = 0.4;
  bool unknown_is_traversable = false;
  int max_expansions = 200000;
  /// Cached results are reused while both end points moved less than this.
  double endpoint_tolerance_m = 0.05;
  bool shorten = true;
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
  const PathSearchConfig& config() const { return config_; }
  PathSearchResult search(const Eigen::Vector3d& a_world_m, const Eigen::Vector3d& b_world_m);
  /// Lengths from `a` to every target with one Dijkstra over the lattice (same rules as
  /// search(): straight when safe, else the lattice path shortened by string pulling; among
  /// equally long lattice paths it may pick another than A*). std::nullopt: no path, or the
  /// shared expansion budget ended. `expansions` (optional) receives the nodes expanded.
  std::vector<std::optional<double>> lengthsFrom(
      const Eigen::Vector3d& a_world_m, const std::vector<Eigen::Vector3d>& targets_world_m,
      int* expansions = nullptr);
  /// Forgets the lattice traversability memo (call when the occupancy changed).
  void clearMemo() { traversable_.clear(); }
  /// Call after each OccupancyMap::insertScan: forgets only the memo entries near the blocks
  /// the scan changed (everything when scans went by unseen), so that consecutive plans reuse
  /// the rest. PathLengthCache::sync calls it.
  void syncWithLastScan();
  size_t memoSize() const { return traversable_.size(); }

 private:
  bool traversable(const VoxelKey& k);
  void syncMemo();
  std::vector<std::pair<VoxelKey, double>> attach(const Eigen::Vector3d& p);
  std::vector<Eigen::Vector3d> shorten(std::vector<Eigen::Vector3d> path) const;
  Eigen::Vector3d center(const VoxelKey& k) const {
    return voxelCenter(k, config_.search_resolution_m);
  }

  const OccupancyMap& occ_;
  PathSearchConfig config_;
  std::unordered_map<VoxelKey, bool, VoxelKeyHash> traversable_;
  uint64_t memo_revision_ = 0;
};

struct PathCacheStats {
  size_t hits = 0;
  size_t misses = 0;
  size_t invalidated = 0;
};

class PathLengthCache {
 public:
  PathLengthCache(const OccupancyMap& occ, PathSearchConfig config = {});

  /// L(a, b) for nodes with stable ids; searched once, then served from the cache.
  std::optional<double> length(uint64_t id_a, const Eigen::Vector3d& a_world_m, uint64_t id_b,
                               const Eigen::Vector3d& b_world_m);
  /// Invalidates what the occupancy's latest scan(s) may have changed.
  void sync();
  /// Forgets every entry that involves node `id` (a viewpoint that was dropped).
  void forget(uint64_t id);
  void clear() { entries_.clear(); }
  size_t size() const { return entries_.size(); }
  const PathCacheStats& stats() const { return stats_; }
  PathSearch& search() { return search_; }

 private:
  struct Entry {
    Eigen::Vector3d a, b;
    std::optional<double> length_m;
    VoxelKey block_lo, block_hi;  ///< box of the path in occupancy blocks, grown by one
  };
  struct PairHash {
    size_t operator()(const std::pair<uint64_t, uint64_t>& p) const noexcept {
      return std::hash<uint64_t>()(p.first * 0x9E3779B97F4A7C15ULL ^ p.second);
    }
  };

  const OccupancyMap& occ_;
  PathSearch search_;
  std::unordered_map<std::pair<uint64_t, uint64_t>, Entry, PairHash> entries_;
  uint64_t synced_revision_ = 0;
  PathCacheStats stats_;
};

}  // namespace efs::planner
