// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/openings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#include "efs_common/config_check.h"
#include "prior_guided_planner/observation_map.h"

namespace efs::planner {

void OpeningConfig::validate() const {
  requireInRange("openings.min_cells", min_cells, 1, 1000000);
  requireInRange("openings.clearance_m", clearance_m, 0.0, 10.0);
  requireInRange("openings.search_radius_m", search_radius_m, 1.0, 100000.0);
}

namespace {

constexpr int kHorizontal[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
/// Opening cells keep this many cells above a floor (0.6 m at 0.3 m) and one below a ceiling.
constexpr int kFloorCells = 2;

bool keyLess(const VoxelKey& a, const VoxelKey& b) {
  return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z);
}

}  // namespace

std::vector<Opening> findOpenings(const OccupancyMap& occ, const Eigen::Vector3d& robot,
                                  const std::optional<Eigen::AlignedBox3d>& bounds,
                                  const OpeningConfig& cfg) {
  cfg.validate();
  std::vector<Opening> out;
  if (!robot.allFinite()) return out;
  const double r2 = cfg.search_radius_m * cfg.search_radius_m;
  auto inBounds = [&](const Eigen::Vector3d& p) { return !bounds || bounds->contains(p); };
  // Opening cells and, per cell, the summed direction to its unknown neighbours.
  std::unordered_map<VoxelKey, Eigen::Vector2d, VoxelKeyHash> cells;
  occ.forEachKnownCell([&](const VoxelKey& k, double, OccupancyState s) {
    if (s != OccupancyState::kFree) return;
    // Not hugging a floor or a ceiling: what lies under a desk or in a roof pocket is no way on,
    // and down there the Mid-360 does not see the floor ahead.
    for (int dz = -kFloorCells; dz <= 1; ++dz)
      if (dz != 0 && occ.isOccupied({k.x, k.y, k.z + dz})) return;
    const Eigen::Vector3d c = occ.center(k);
    if ((c - robot).head<2>().squaredNorm() > r2 || !inBounds(c)) return;
    Eigen::Vector2d dir = Eigen::Vector2d::Zero();
    int unknown = 0;
    for (const auto& d : kHorizontal) {
      const VoxelKey n{k.x + d[0], k.y + d[1], k.z};
      // The box's own edge is not a way on.
      if (occ.isUnknown(n) && inBounds(occ.center(n))) {
        dir += Eigen::Vector2d(d[0], d[1]);
        ++unknown;
      }
    }
    if (unknown > 0) cells.emplace(k, dir);
  });
  // 26-connected clusters.
  std::unordered_set<VoxelKey, VoxelKeyHash> pending;
  for (const auto& [k, unused] : cells) pending.insert(k);
  while (!pending.empty()) {
    const std::vector<VoxelKey> cluster = takeComponent26(*pending.begin(), pending);
    if (static_cast<int>(cluster.size()) < cfg.min_cells) continue;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    Eigen::Vector2d dir = Eigen::Vector2d::Zero();
    VoxelKey smallest = cluster.front();
    for (const VoxelKey& k : cluster) {
      centroid += occ.center(k);
      dir += cells.at(k);
      if (keyLess(k, smallest)) smallest = k;
    }
    centroid /= static_cast<double>(cluster.size());
    // The viewpoint: the safe cluster cell nearest the centroid, a cell back from the unknown
    // side when that one is safe too (the sensor then sees through the opening, not into it).
    const Eigen::Vector2d away = dir.squaredNorm() > 0.0 ? Eigen::Vector2d(-dir.normalized())
                                                         : Eigen::Vector2d::Zero();
    std::optional<Eigen::Vector3d> best;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (const VoxelKey& k : cluster) {
      const Eigen::Vector3d c = occ.center(k);
      const double d2 = (c - centroid).squaredNorm();
      if (d2 >= best_d2 || !occ.isSafe(c, cfg.clearance_m, false)) continue;
      best_d2 = d2;
      best = c;
    }
    if (!best) continue;
    const Eigen::Vector3d back =
        *best + occ.resolution() * Eigen::Vector3d(away.x(), away.y(), 0.0);
    if (occ.isSafe(back, cfg.clearance_m, false)) best = back;
    Opening o;
    // Ids live far above the observation viewpoints' (which count up from 0).
    const size_t h = VoxelKeyHash()(smallest);
    o.id = (1 << 30) + static_cast<int>(h % (size_t{1} << 29));
    o.viewpoint_world_m = *best;
    o.yaw_rad = dir.squaredNorm() > 0.0 ? std::atan2(dir.y(), dir.x()) : 0.0;
    o.cells = static_cast<int>(cluster.size());
    out.push_back(o);
  }
  std::sort(out.begin(), out.end(), [](const Opening& a, const Opening& b) {
    return a.cells != b.cells ? a.cells > b.cells : a.id < b.id;
  });
  return out;
}

}  // namespace efs::planner
