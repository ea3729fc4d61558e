// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/astar.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "efs_common/config_check.h"

namespace efs::traj {

void AStarConfig::validate() const {
  requireInRange("astar.goal_search_radius_m", goal_search_radius_m, 0.0, 10.0);
  requireInRange("astar.start_escape_radius_m", start_escape_radius_m, 0.0, 10.0);
  requireInRange("astar.max_expansions", max_expansions, 1, 100000000);
  requireInRange("astar.heuristic_weight", heuristic_weight, 1.0, 10.0);
  requireInRange("astar.narrow_clearance_m", narrow_clearance_m, 0.0, 10.0);
  requireInRange("astar.unknown_cost_factor", unknown_cost_factor, 1.0, 100.0);
  requireInRange("astar.unknown_height_margin_m", unknown_height_margin_m, 0.0, 1000.0);
}

const char* toString(AStarStatus s) {
  switch (s) {
    case AStarStatus::kSuccess:
      return "success";
    case AStarStatus::kStartOutside:
      return "start_outside_window";
    case AStarStatus::kStartInCollision:
      return "start_in_collision";
    case AStarStatus::kGoalOutside:
      return "goal_outside_window";
    case AStarStatus::kGoalBlocked:
      return "goal_blocked";
    case AStarStatus::kNoPath:
      return "no_path";
    case AStarStatus::kExpansionLimit:
      return "expansion_limit";
  }
  return "?";
}

AStarPlanner::AStarPlanner(const AStarConfig& cfg) : cfg_(cfg) { cfg_.validate(); }

namespace {
// Octile distance in 3D, in cells: sorted |d| = (a >= b >= c).
inline double octile(const VoxelKey& a, const VoxelKey& b) {
  double d[3] = {std::abs(static_cast<double>(a.x - b.x)), std::abs(static_cast<double>(a.y - b.y)),
                 std::abs(static_cast<double>(a.z - b.z))};
  std::sort(d, d + 3);  // d[0] <= d[1] <= d[2]
  static const double s2 = std::sqrt(2.0), s3 = std::sqrt(3.0);
  return (s3 - s2) * d[0] + (s2 - 1.0) * d[1] + d[2];
}

struct Node {
  VoxelKey key;
  double g;
  int parent;
  bool closed;
};
}  // namespace

AStarPlanner::Band AStarPlanner::unknownBand(double z0_m, double z1_m, double cell_m) const {
  const double m = cfg_.unknown_height_margin_m, tol = 0.5 * cell_m;
  // On the way down only the start's height: unknown space below the vehicle is the LiDAR's
  // blind cone, not space it has not reached yet (seen: descending 1.4 m to a viewpoint, the
  // route crossed unknown cells beside it that were a rock, and the vehicle hit it at 2 m/s).
  // Otherwise the margin is the goal's, not the start's: a margin around the start moves with
  // the vehicle, and each replan took it half a metre lower (seen in ed21: a door whose lower
  // sides were unseen, 1.24 -> 1.03 -> 0.87 -> 0.58 m in four plans, the floor hit at 0.40 m;
  // the goal stayed at 1.2-1.35 m). The same holds upwards. The start's own cell (its centre
  // may lie half a cell beyond it) stays usable.
  const double lo = z1_m < z0_m ? z0_m - m : std::min(z0_m - tol, z1_m - m);
  const double hi = z1_m > z0_m ? z1_m + m : std::max(z0_m + tol, z1_m + m);
  return {lo, hi};
}

bool AStarPlanner::traversable(const LocalGrid& grid, const VoxelKey& k,
                               const Band& unknown_band) const {
  if (grid.isBlocked(k, cfg_.unknown_is_free, cfg_.narrow_clearance_m)) return false;
  if (!cfg_.unknown_is_free || grid.state(k) != CellState::kUnknown) return true;
  const double z = grid.center(k).z();
  return z >= unknown_band.lo_z_m && z <= unknown_band.hi_z_m;
}

bool AStarPlanner::segmentClear(const LocalGrid& grid, const Eigen::Vector3d& a,
                                const Eigen::Vector3d& b, const Band& unknown_band) const {
  return traverseCells(a, b, grid.resolution(),
                       [&](const VoxelKey& k) { return traversable(grid, k, unknown_band); });
}

bool AStarPlanner::lineOfSight(const LocalGrid& grid, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b) const {
  return segmentClear(grid, a, b, unknownBand(a.z(), b.z(), grid.resolution()));
}

bool AStarPlanner::nearestFree(const LocalGrid& grid, const VoxelKey& k, double radius_m,
                               VoxelKey* out) const {
  const double z = grid.center(k).z();
  return nearestTraversable(grid, k, radius_m, unknownBand(z, z, grid.resolution()), out);
}

bool AStarPlanner::nearestTraversable(const LocalGrid& grid, const VoxelKey& k, double radius_m,
                                      const Band& unknown_band, VoxelKey* out) const {
  const int r = static_cast<int>(std::ceil(radius_m / grid.resolution()));
  const double r2 = std::pow(radius_m / grid.resolution(), 2) + 1e-9;
  double best = 1e300;
  for (int dx = -r; dx <= r; ++dx)
    for (int dy = -r; dy <= r; ++dy)
      for (int dz = -r; dz <= r; ++dz) {
        const double d2 = dx * dx + dy * dy + dz * dz;
        if (d2 > r2 || d2 >= best) continue;
        const VoxelKey n{k.x + dx, k.y + dy, k.z + dz};
        if (!traversable(grid, n, unknown_band)) continue;
        best = d2;
        *out = n;
      }
  return best < 1e300;
}

AStarResult AStarPlanner::plan(const LocalGrid& grid, const Eigen::Vector3d& start,
                               const Eigen::Vector3d& goal_in) const {
  AStarResult res;
  const double res_m = grid.resolution();
  if (!start.allFinite() || !grid.inWindow(start)) {
    res.status = AStarStatus::kStartOutside;
    return res;
  }
  Eigen::Vector3d goal = goal_in;
  if (!goal.allFinite()) {
    res.status = AStarStatus::kGoalOutside;
    return res;
  }
  if (!grid.inWindow(goal)) {
    if (!cfg_.clamp_goal_to_window) {
      res.status = AStarStatus::kGoalOutside;
      return res;
    }
    // Pull the goal along the start->goal line to just inside the window.
    const Eigen::Vector3d lo = grid.windowMin().array() + 0.5 * res_m;
    const Eigen::Vector3d hi = grid.windowMax().array() - 0.5 * res_m;
    double s = 1.0;
    for (int a = 0; a < 3; ++a) {
      const double d = goal[a] - start[a];
      if (goal[a] > hi[a]) s = std::min(s, (hi[a] - start[a]) / d);
      if (goal[a] < lo[a]) s = std::min(s, (lo[a] - start[a]) / d);
    }
    goal = start + std::max(0.0, s) * (goal - start);
    res.goal_adjusted = true;
  }
  VoxelKey sk = grid.key(start), gk = grid.key(goal);
  const Band band = unknownBand(start.z(), goal.z(), res_m);
  Eigen::Vector3d escape_point = start;
  if (!traversable(grid, sk, band)) {
    VoxelKey free_k;
    if (!nearestTraversable(grid, sk, cfg_.start_escape_radius_m, band, &free_k)) {
      res.status = AStarStatus::kStartInCollision;
      return res;
    }
    sk = free_k;
    escape_point = grid.center(free_k);
    res.start_escaped = true;
  }
  if (!traversable(grid, gk, band)) {
    VoxelKey free_k;
    if (!nearestTraversable(grid, gk, cfg_.goal_search_radius_m, band, &free_k)) {
      res.status = AStarStatus::kGoalBlocked;
      return res;
    }
    gk = free_k;
    goal = grid.center(free_k);
    res.goal_adjusted = true;
  }

  std::vector<Node> nodes;
  nodes.reserve(4096);
  // Dense per-cell scratch (node index valid when the stamp matches this search): no hashing and
  // no clearing between searches.
  if (stamp_.size() != grid.cellCount()) {
    stamp_.assign(grid.cellCount(), 0);
    node_of_.assign(grid.cellCount(), -1);
    search_id_ = 0;
  }
  if (++search_id_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    search_id_ = 1;
  }
  auto lookup = [&](const VoxelKey& k) -> int {
    const size_t sl = grid.slot(k);
    return stamp_[sl] == search_id_ ? node_of_[sl] : -1;
  };
  auto remember = [&](const VoxelKey& k, int idx) {
    const size_t sl = grid.slot(k);
    stamp_[sl] = search_id_;
    node_of_[sl] = idx;
  };
  // Ties in f are broken toward larger g (deeper nodes): in open space many cells share the same
  // f, and preferring the deepest one avoids expanding the whole tie plateau. Optimality is kept
  // because the order among equal f does not matter for a consistent heuristic.
  struct QE {
    double f, g;
    int node;
    bool operator>(const QE& o) const { return f > o.f || (f == o.f && g < o.g); }
  };
  std::priority_queue<QE, std::vector<QE>, std::greater<QE>> open;
  nodes.push_back({sk, 0.0, -1, false});
  remember(sk, 0);
  const double hw = cfg_.heuristic_weight;
  open.push({hw * octile(sk, gk), 0.0, 0});
  static const double kStep[4] = {0.0, 1.0, std::sqrt(2.0), std::sqrt(3.0)};
  int found = -1;
  while (!open.empty()) {
    const int ni = open.top().node;
    open.pop();
    if (nodes[ni].closed) continue;
    nodes[ni].closed = true;
    if (nodes[ni].key == gk) {
      found = ni;
      break;
    }
    if (++res.expansions > cfg_.max_expansions) {
      res.status = AStarStatus::kExpansionLimit;
      return res;
    }
    const VoxelKey k = nodes[ni].key;
    const double g = nodes[ni].g;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const int m = std::abs(dx) + std::abs(dy) + std::abs(dz);
          if (m == 0) continue;
          const VoxelKey nk{k.x + dx, k.y + dy, k.z + dz};
          if (!traversable(grid, nk, band)) continue;
          const double step =
              cfg_.unknown_cost_factor > 1.0 && grid.state(nk) == CellState::kUnknown
                  ? cfg_.unknown_cost_factor * kStep[m]
                  : kStep[m];
          const double ng = g + step;
          int idx = lookup(nk);
          if (idx < 0) {
            idx = static_cast<int>(nodes.size());
            nodes.push_back({nk, ng, ni, false});
            remember(nk, idx);
          } else {
            if (nodes[idx].closed || ng >= nodes[idx].g - 1e-12) continue;
            nodes[idx].g = ng;
            nodes[idx].parent = ni;
          }
          open.push({ng + hw * octile(nk, gk), ng, idx});
        }
  }
  if (found < 0) {
    res.status = AStarStatus::kNoPath;
    return res;
  }
  std::vector<Eigen::Vector3d> cells;
  for (int i = found; i >= 0; i = nodes[i].parent) cells.push_back(grid.center(nodes[i].key));
  std::reverse(cells.begin(), cells.end());
  // Exact endpoints replace the centres of their cells (they lie in those cells).
  cells.front() = escape_point;
  cells.back() = goal;
  if (res.start_escaped) cells.insert(cells.begin(), start);
  res.grid_path_world_m = cells;
  res.grid_path_length_m = nodes[found].g * res_m;

  if (!cfg_.shortcut || cells.size() <= 2) {
    res.path_world_m = cells;
  } else {
    // Greedy forward shortcuts; the escape segment (through blocked cells) is kept as it is.
    auto& out = res.path_world_m;
    size_t anchor = 0;
    out.push_back(cells[0]);
    if (res.start_escaped) {
      out.push_back(cells[1]);
      anchor = 1;
    }
    while (anchor + 1 < cells.size()) {
      size_t j = anchor + 1;
      while (j + 1 < cells.size() && segmentClear(grid, cells[anchor], cells[j + 1], band)) ++j;
      out.push_back(cells[j]);
      anchor = j;
    }
  }
  res.status = AStarStatus::kSuccess;
  return res;
}

}  // namespace efs::traj
