// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/voxel_key_table.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>
#include <vector>

namespace efs {
namespace {

TEST(VoxelKeyTable, FindsExactlyTheInsertedKeys) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> coord(-3000, 3000);
  std::vector<VoxelKey> keys;
  std::set<std::tuple<int, int, int>> truth;
  for (int i = 0; i < 20000; ++i) {
    const VoxelKey k{coord(rng), coord(rng), coord(rng) / 100};
    keys.push_back(k);
    keys.push_back(k);  // duplicates are stored once
    truth.insert({k.x, k.y, k.z});
  }
  const VoxelKeyTable table(keys);
  EXPECT_EQ(table.size(), truth.size());
  EXPECT_GE(table.capacity(), 2 * table.size());
  std::set<size_t> slots;
  for (const auto& [x, y, z] : truth) {
    const auto slot = table.find({x, y, z});
    ASSERT_TRUE(slot.has_value());
    slots.insert(*slot);
  }
  EXPECT_EQ(slots.size(), truth.size()) << "two keys share a slot";
  int absent_found = 0;
  for (int i = 0; i < 20000; ++i) {
    const VoxelKey k{coord(rng), coord(rng), coord(rng) / 100};
    if (truth.count({k.x, k.y, k.z}) == 0 && table.find(k)) ++absent_found;
  }
  EXPECT_EQ(absent_found, 0);
}

TEST(VoxelKeyTable, EmptyTableFindsNothing) {
  const VoxelKeyTable empty;
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_FALSE(empty.find({0, 0, 0}).has_value());
  const VoxelKeyTable from_empty(std::vector<VoxelKey>{});
  EXPECT_FALSE(from_empty.find({1, 2, 3}).has_value());
}

}  // namespace
}  // namespace efs
