// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The free space a vehicle could reach from where it starts: the free voxels of a VoxelWorld
// 6-connected to a seed. Coverage's ground truth is the surface seen from this space only: an
// imported building's grid also holds the space outside its walls (its bounding box and the
// importer's margin, floored and ceiled) and rooms with no open door, whose surfaces no flight
// can see. Counting them capped the ed21 building at 55 % of its surface.
//
// Connectivity ignores the vehicle's size (a gap one voxel wide connects), so what lies behind
// a gap too narrow to fly still counts: the ground truth errs towards too much surface, never
// too little.
// The fill is brick-wise: an all-free brick is one step and only bricks cut by a surface are
// walked voxel by voxel, so the SubT-scale world takes seconds rather than its 8e9 voxels.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "marsim_worlds/voxel_world.h"

namespace efs::sim {

class FreeSpaceComponent {
 public:
  /// The component of the free voxel holding `seed_m`; empty if that voxel is occupied or outside
  /// the grid, or the seed is not finite. `world` must outlive this object and not change while
  /// it is used.
  FreeSpaceComponent(const VoxelWorld& world, const Eigen::Vector3d& seed_m);

  /// True if the voxel holding `p_m` belongs to the component (false for a non-finite point).
  bool contains(const Eigen::Vector3d& p_m) const;
  std::size_t voxelCount() const { return voxel_count_; }

 private:
  void reach(const Eigen::Vector3i& v, std::vector<Eigen::Vector3i>* stack);
  void expand(const Eigen::Vector3i& v, std::vector<Eigen::Vector3i>* stack);
  int64_t brickIndex(const Eigen::Vector3i& brick) const;
  static int bitOf(const Eigen::Vector3i& v);

  const VoxelWorld* world_;
  std::vector<uint8_t> empty_brick_reached_;  ///< per brick; meaningful for all-free bricks
  /// Reached voxels of bricks cut by a surface, bit layout as VoxelWorld::BrickMask.
  std::unordered_map<int64_t, VoxelWorld::BrickMask> masked_reached_;
  std::size_t voxel_count_ = 0;
};

}  // namespace efs::sim
