// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/voxel_key.h"

#include <gtest/gtest.h>

#include <unordered_set>

namespace efs {
namespace {

TEST(VoxelKey, NegativeCoordinatesFloorTowardsMinusInfinity) {
  const VoxelKey k = toVoxelKey(Eigen::Vector3d(-0.01, 0.29, 0.31), 0.3);
  EXPECT_EQ(k.x, -1);
  EXPECT_EQ(k.y, 0);
  EXPECT_EQ(k.z, 1);
}

TEST(VoxelKey, CenterMapsBackToSameKey) {
  for (int i = -50; i <= 50; i += 7) {
    const VoxelKey k{i, -i, i / 2};
    EXPECT_EQ(toVoxelKey(voxelCenter(k, 0.2), 0.2), k);
  }
}

TEST(VoxelKey, HashSeparatesNeighbours) {
  std::unordered_set<VoxelKey, VoxelKeyHash> keys;
  for (int x = -5; x <= 5; ++x)
    for (int y = -5; y <= 5; ++y)
      for (int z = -5; z <= 5; ++z) keys.insert({x, y, z});
  EXPECT_EQ(keys.size(), 11u * 11u * 11u);
}

TEST(CellKey2d, DistinctForEveryCellAcrossTheAxesSignsAndPacksEachIndex) {
  std::unordered_set<long long> keys;
  const long long big = 2147483647LL;  // the largest index the 32-bit halves hold
  for (long long x : {-big - 1, -2LL, -1LL, 0LL, 1LL, big})
    for (long long y : {-big - 1, -2LL, -1LL, 0LL, 1LL, big}) keys.insert(cellKey2d(x, y));
  EXPECT_EQ(keys.size(), 36u);
  // x in the high half, y's low 32 bits in the low half.
  EXPECT_EQ(cellKey2d(1, 2), (1LL << 32) + 2);
  EXPECT_EQ(cellKey2d(0, -1), 0xffffffffLL);
  EXPECT_EQ(cellKey2d(-1, 0), static_cast<long long>(0xffffffff00000000ULL));
}

}  // namespace
}  // namespace efs
