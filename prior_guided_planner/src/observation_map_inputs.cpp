// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/observation_map_inputs.h"

#include <stdexcept>
#include <string>

namespace efs::planner {

std::vector<PlanViewpoint> toPlanViewpoints(const ViewpointManager& viewpoints) {
  std::vector<PlanViewpoint> out;
  for (const Viewpoint& v : viewpoints.all()) {
    PlanViewpoint p;
    p.id = v.id;
    p.position_world_m = v.position_world_m;
    p.yaw_rad = v.yaw_rad;
    out.push_back(p);
  }
  return out;
}

ObservationQuery makeObservationQuery(const ObservationMap& map) {
  return [&map](const Eigen::Vector2d& c, double radius_m) {
    switch (map.bestLevelNear2d(c, radius_m)) {
      case 2:
        return ObservationLevel::kWellObserved;
      case 1:
        return ObservationLevel::kPoorlyObserved;
      default:
        return ObservationLevel::kNone;
    }
  };
}

PathLengthFn makePathLengthFn(PathLengthCache& cache, const Eigen::Vector3d& robot,
                              const std::vector<PlanViewpoint>& vps) {
  return [&cache, robot, &vps](int from, int to) {
    auto node = [&](int i) -> std::pair<uint64_t, Eigen::Vector3d> {
      if (i == kRobotNode) return {kRobotPathNodeId, robot};
      if (i < 0 || i >= static_cast<int>(vps.size()) || vps[i].id < 0)
        throw std::out_of_range("path length: no planner node " + std::to_string(i));
      return {static_cast<uint64_t>(vps[i].id), vps[i].position_world_m};
    };
    if (from == to) return 0.0;
    const auto [ia, a] = node(from);
    const auto [ib, b] = node(to);
    const std::optional<double> l = cache.length(ia, a, ib, b);
    return l ? *l : kUnreachable;
  };
}

PathLengthFn makePathLengthFn(PathLengthCache& cache, const std::vector<double>& robot_len,
                              const std::vector<PlanViewpoint>& vps) {
  if (robot_len.size() != vps.size())
    throw std::invalid_argument("path length: " + std::to_string(robot_len.size()) +
                                " robot lengths for " + std::to_string(vps.size()) + " viewpoints");
  return [&cache, &robot_len, &vps](int from, int to) {
    if (from == to) return 0.0;
    auto check = [&](int i) {
      if (i < 0 || i >= static_cast<int>(vps.size()) || vps[i].id < 0)
        throw std::out_of_range("path length: no planner node " + std::to_string(i));
    };
    if (from == kRobotNode || to == kRobotNode) {
      const int v = from == kRobotNode ? to : from;
      check(v);
      return robot_len[v];
    }
    check(from);
    check(to);
    const std::optional<double> l =
        cache.length(static_cast<uint64_t>(vps[from].id), vps[from].position_world_m,
                     static_cast<uint64_t>(vps[to].id), vps[to].position_world_m);
    return l ? *l : kUnreachable;
  };
}

}  // namespace efs::planner
