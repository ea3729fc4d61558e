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
  std::set<size_t> indices;
  for (const auto& [x, y, z] : truth) {
    const auto index = table.find({x, y, z});
    ASSERT_TRUE(index.has_value());
    ASSERT_LT(*index, table.size());
    EXPECT_EQ(table.key(*index), (VoxelKey{x, y, z}));
    indices.insert(*index);
  }
  EXPECT_EQ(indices.size(), truth.size()) << "two keys share an index";
  int absent_found = 0;
  for (int i = 0; i < 20000; ++i) {
    const VoxelKey k{coord(rng), coord(rng), coord(rng) / 100};
    if (truth.count({k.x, k.y, k.z}) == 0 && table.find(k)) ++absent_found;
  }
  EXPECT_EQ(absent_found, 0);
}

TEST(VoxelKeyTable, GrowsKeepingTheIndicesOfFirstInsertion) {
  // Keys one block apart along each axis and negative ones: the occupancy map's block keys.
  VoxelKeyTable table;
  std::vector<VoxelKey> order;
  for (int z = -2; z <= 2; ++z)
    for (int y = -40; y < 40; ++y)
      for (int x = -40; x < 40; ++x) {
        const VoxelKey k{x, y, z};
        EXPECT_EQ(table.insert(k), order.size());
        order.push_back(k);
      }
  // Inserted again (through several rehashes since): the first index, nothing added.
  for (size_t i = 0; i < order.size(); i += 7) EXPECT_EQ(table.insert(order[i]), i);
  EXPECT_EQ(table.size(), order.size());
  for (size_t i = 0; i < order.size(); ++i) {
    ASSERT_EQ(table.find(order[i]), std::optional<size_t>(i));
    ASSERT_EQ(table.key(i), order[i]);
  }
  EXPECT_FALSE(table.find({40, 0, 0}).has_value());
  EXPECT_GT(table.memoryBytes(), order.size() * sizeof(VoxelKey));
  table.clear();
  EXPECT_TRUE(table.empty());
  EXPECT_FALSE(table.find(order.front()).has_value());
  EXPECT_EQ(table.insert(order.back()), 0u);
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
