// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The plain voxel-by-voxel flood fill, for tests: the reference the brick-wise
// FreeSpaceComponent must match, and the reachability check of the generated worlds.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

namespace efs::sim::testing {

struct FloodFillCount {
  std::size_t passable = 0;  ///< voxels of the box where `passable` holds
  std::size_t reached = 0;   ///< of those, 6-connected to the start through passable voxels
};

/// Over the voxel box [lo, hi] (inclusive; `start` must lie in it): `passable(v)` is asked once
/// per voxel. Nothing is reached from a start that is not passable.
template <class Passable>
FloodFillCount plainFloodFill(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi,
                              const Eigen::Vector3i& start, const Passable& passable) {
  const Eigen::Vector3i n = hi - lo + Eigen::Vector3i::Ones();
  const auto index = [&](const Eigen::Vector3i& v) {
    const Eigen::Vector3i d = v - lo;
    return d.x() +
           static_cast<std::size_t>(n.x()) * (d.y() + static_cast<std::size_t>(n.y()) * d.z());
  };
  FloodFillCount count;
  std::vector<uint8_t> open(static_cast<std::size_t>(n.prod()), 0);  // 1 passable, 2 reached
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x)
        if (passable(Eigen::Vector3i(x, y, z))) {
          open[index({x, y, z})] = 1;
          ++count.passable;
        }
  if (open[index(start)] != 1) return count;
  std::deque<Eigen::Vector3i> queue{start};
  open[index(start)] = 2;
  while (!queue.empty()) {
    const Eigen::Vector3i v = queue.front();
    queue.pop_front();
    ++count.reached;
    for (int a = 0; a < 3; ++a) {
      for (const int s : {-1, 1}) {
        Eigen::Vector3i u = v;
        u[a] += s;
        if (u[a] < lo[a] || u[a] > hi[a] || open[index(u)] != 1) continue;
        open[index(u)] = 2;
        queue.push_back(u);
      }
    }
  }
  return count;
}

}  // namespace efs::sim::testing
