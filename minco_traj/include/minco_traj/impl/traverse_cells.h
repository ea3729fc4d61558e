// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#pragma once

#include <cmath>
#include <limits>

namespace efs::traj {

template <typename Visit>
bool traverseCells(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double res,
                   Visit&& visit) {
  VoxelKey cur = toVoxelKey(from, res);
  const VoxelKey end = toVoxelKey(to, res);
  const Eigen::Vector3d d = to - from;
  int step[3];
  double t_max[3], t_delta[3];
  int32_t* cur_c[3] = {&cur.x, &cur.y, &cur.z};
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 0) {
      step[a] = 1;
      t_delta[a] = res / d[a];
      t_max[a] = ((*cur_c[a] + 1) * res - from[a]) / d[a];
    } else if (d[a] < 0) {
      step[a] = -1;
      t_delta[a] = -res / d[a];
      t_max[a] = (*cur_c[a] * res - from[a]) / d[a];
    } else {
      step[a] = 0;
      t_delta[a] = std::numeric_limits<double>::infinity();
      t_max[a] = std::numeric_limits<double>::infinity();
    }
  }
  const int max_steps = std::abs(end.x - cur.x) + std::abs(end.y - cur.y) + std::abs(end.z - cur.z);
  for (int i = 0; i <= max_steps; ++i) {
    if (!visit(static_cast<const VoxelKey&>(cur))) return false;
    if (cur == end) break;
    int a = 0;
    if (t_max[1] < t_max[a]) a = 1;
    if (t_max[2] < t_max[a]) a = 2;
    if (std::isinf(t_max[a]) || t_max[a] > 1.0 + 1e-9) break;
    *cur_c[a] += step[a];
    t_max[a] += t_delta[a];
  }
  return true;
}

}  // namespace efs::traj
