// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/goal_along_path.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace efs::planner {

Eigen::Vector3d goalAlongPath(const std::vector<Eigen::Vector3d>& path, double max_length_m,
                              double outward_after_m,
                              const std::function<bool(const Eigen::Vector3d&)>& within_reach) {
  if (path.empty()) throw std::invalid_argument("goalAlongPath: empty path");
  constexpr double kStep_m = 0.1;
  const Eigen::Vector3d& from = path.front();
  Eigen::Vector3d last = from;
  double walked = 0.0, farthest = 0.0;
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector3d a = path[i], b = path[i + 1];
    const double len = (b - a).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(len / kStep_m)));
    for (int k = 1; k <= n; ++k) {
      const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(k) / n);
      const double along = walked + len * k / n;
      if (!within_reach(p) || along > max_length_m) return last;
      const double d = (p - from).norm();
      if (along > outward_after_m && d < farthest - kStep_m) return last;
      farthest = std::max(farthest, d);
      last = p;
    }
    walked += len;
  }
  return last;
}

}  // namespace efs::planner
