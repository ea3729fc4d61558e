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

}  // namespace
}  // namespace efs
