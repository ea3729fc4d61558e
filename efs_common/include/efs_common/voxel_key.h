// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Integer voxel coordinates and their hash, shared by every sparse map of the suite (simulator
// ground truth, observation map, local occupancy) so that they agree on cell boundaries.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace efs {

struct VoxelKey {
  int32_t x = 0, y = 0, z = 0;
  bool operator==(const VoxelKey& o) const { return x == o.x && y == o.y && z == o.z; }
  bool operator!=(const VoxelKey& o) const { return !(*this == o); }
};

/// A total order of keys (x, then y, then z): tie-breaks that must not depend on hash order.
inline bool voxelKeyLess(const VoxelKey& a, const VoxelKey& b) {
  return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z);
}

struct VoxelKeyHash {
  std::size_t operator()(const VoxelKey& k) const noexcept {
    // Large odd primes decorrelate the axes (Teschner et al. 2003 spatial hashing).
    return static_cast<std::size_t>(
        (static_cast<uint64_t>(static_cast<uint32_t>(k.x)) * 73856093ULL) ^
        (static_cast<uint64_t>(static_cast<uint32_t>(k.y)) * 19349663ULL) ^
        (static_cast<uint64_t>(static_cast<uint32_t>(k.z)) * 83492791ULL));
  }
};

/// Cell index of a point; cells are [i*res, (i+1)*res) along each axis.
inline VoxelKey toVoxelKey(const Eigen::Vector3d& p_m, double resolution_m) {
  return {static_cast<int32_t>(std::floor(p_m.x() / resolution_m)),
          static_cast<int32_t>(std::floor(p_m.y() / resolution_m)),
          static_cast<int32_t>(std::floor(p_m.z() / resolution_m))};
}

/// One integer for a 2D grid cell: each index's low 32 bits, x in the high half. Packed as unsigned
/// (shifting a negative signed value is undefined before C++20); the same value a signed shift
/// gives on two's-complement machines.
inline long long cellKey2d(long long ix, long long iy) {
  return static_cast<long long>((static_cast<uint64_t>(ix) << 32) ^
                                (static_cast<uint64_t>(iy) & 0xffffffffULL));
}

inline Eigen::Vector3d voxelCenter(const VoxelKey& k, double resolution_m) {
  return {(k.x + 0.5) * resolution_m, (k.y + 0.5) * resolution_m, (k.z + 0.5) * resolution_m};
}

}  // namespace efs
