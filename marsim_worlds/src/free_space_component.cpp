// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/free_space_component.h"

namespace efs::sim {
namespace {

constexpr int kEdge = VoxelWorld::kBrickEdge;

Eigen::Vector3i brickOf(const Eigen::Vector3i& v) {
  return {v.x() >> VoxelWorld::kBrickShift, v.y() >> VoxelWorld::kBrickShift,
          v.z() >> VoxelWorld::kBrickShift};
}

}  // namespace

FreeSpaceComponent::FreeSpaceComponent(const VoxelWorld& world, const Eigen::Vector3d& seed_m)
    : world_(&world),
      empty_brick_reached_(static_cast<size_t>(world.dimsBricks().cast<int64_t>().prod()), 0) {
  if (!seed_m.allFinite()) return;  // voxelOf would cast a NaN to int
  std::vector<Eigen::Vector3i> stack;
  reach(world.voxelOf(seed_m), &stack);
  while (!stack.empty()) {
    const Eigen::Vector3i v = stack.back();
    stack.pop_back();
    expand(v, &stack);
  }
}

int64_t FreeSpaceComponent::brickIndex(const Eigen::Vector3i& b) const {
  const Eigen::Vector3i& n = world_->dimsBricks();
  return b.x() + static_cast<int64_t>(n.x()) * (b.y() + static_cast<int64_t>(n.y()) * b.z());
}

int FreeSpaceComponent::bitOf(const Eigen::Vector3i& v) {
  return (v.x() & VoxelWorld::kBrickMask) + kEdge * (v.y() & VoxelWorld::kBrickMask);
}

void FreeSpaceComponent::reach(const Eigen::Vector3i& v, std::vector<Eigen::Vector3i>* stack) {
  if (!world_->inGrid(v)) return;
  const Eigen::Vector3i b = brickOf(v);
  const int32_t slot = world_->brickSlot(b);
  if (slot == VoxelWorld::kFullBrick) return;
  const int64_t index = brickIndex(b);
  if (slot == VoxelWorld::kEmptyBrick) {
    uint8_t& reached = empty_brick_reached_[static_cast<size_t>(index)];
    if (reached) return;
    reached = 1;
    voxel_count_ += kEdge * kEdge * kEdge;
    stack->push_back(v);  // stands for the whole brick
    return;
  }
  if (world_->occupied(v)) return;
  uint64_t& row = masked_reached_[index].rows[static_cast<size_t>(v.z() & VoxelWorld::kBrickMask)];
  const uint64_t bit = uint64_t{1} << bitOf(v);
  if (row & bit) return;
  row |= bit;
  ++voxel_count_;
  stack->push_back(v);
}

void FreeSpaceComponent::expand(const Eigen::Vector3i& v, std::vector<Eigen::Vector3i>* stack) {
  const Eigen::Vector3i b = brickOf(v);
  if (world_->brickSlot(b) != VoxelWorld::kEmptyBrick) {
    for (int axis = 0; axis < 3; ++axis) {
      for (const int step : {-1, 1}) {
        Eigen::Vector3i u = v;
        u[axis] += step;
        reach(u, stack);
      }
    }
    return;
  }
  // A whole free brick: across each face, one step into a free or full neighbour brick decides
  // it; a neighbour cut by a surface is entered voxel by voxel along the shared face.
  const Eigen::Vector3i lo = b * kEdge;
  for (int axis = 0; axis < 3; ++axis) {
    for (const int side : {-1, 1}) {
      Eigen::Vector3i nb = b;
      nb[axis] += side;
      Eigen::Vector3i first = lo;
      first[axis] = side < 0 ? lo[axis] - 1 : lo[axis] + kEdge;
      if (!world_->inGrid(first)) continue;
      if (world_->brickSlot(nb) < 0) {  // all free or all occupied
        reach(first, stack);
        continue;
      }
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      for (int i = 0; i < kEdge; ++i) {
        for (int j = 0; j < kEdge; ++j) {
          Eigen::Vector3i u = first;
          u[a1] += i;
          u[a2] += j;
          reach(u, stack);
        }
      }
    }
  }
}

bool FreeSpaceComponent::contains(const Eigen::Vector3d& p_m) const {
  if (!p_m.allFinite()) return false;
  const Eigen::Vector3i v = world_->voxelOf(p_m);
  if (!world_->inGrid(v)) return false;
  const Eigen::Vector3i b = brickOf(v);
  const int32_t slot = world_->brickSlot(b);
  if (slot == VoxelWorld::kFullBrick) return false;
  const int64_t index = brickIndex(b);
  if (slot == VoxelWorld::kEmptyBrick) return empty_brick_reached_[static_cast<size_t>(index)] != 0;
  const auto it = masked_reached_.find(index);
  if (it == masked_reached_.end()) return false;
  return (it->second.rows[static_cast<size_t>(v.z() & VoxelWorld::kBrickMask)] >> bitOf(v)) & 1u;
}

}  // namespace efs::sim
