// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/path_length.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "efs_common/config_check.h"
#include "prior_guided_planner/observation_map.h"

namespace efs::planner {
namespace {

struct LatticeNode {
  double g;
  VoxelKey parent;
  bool closed;
  bool has_parent;
};

// The lattice part shared by the A* (one target) and the Dijkstra (many targets): best-first
// expansion over the 26-connected lattice with parent links.
class Lattice {
 public:
  explicit Lattice(double resolution_m) : s_(resolution_m) {}

  /// A start node with cost g and priority f (= g + heuristic).
  void seed(const VoxelKey& k, double g, double f) {
    auto [it, inserted] = nodes_.try_emplace(k, LatticeNode{g, k, false, false});
    if (!inserted) {
      if (it->second.g <= g) return;
      it->second = LatticeNode{g, k, false, false};
    }
    open_.push({f, k});
  }
  /// Closes the open node of least priority; returns its (g, key), nullopt when none is left.
  std::optional<std::pair<double, VoxelKey>> pop(double* priority) {
    while (!open_.empty()) {
      const auto [f, k] = open_.top();
      open_.pop();
      LatticeNode& n = nodes_[k];
      if (n.closed) continue;
      n.closed = true;
      if (priority) *priority = f;
      return std::make_pair(n.g, k);
    }
    return std::nullopt;
  }
  /// Opens or improves the traversable neighbours of k (cost g); `h` is the heuristic.
  template <typename Traversable, typename Heuristic>
  void relax(const VoxelKey& k, double g, Traversable&& traversable, Heuristic&& h) {
    for (const VoxelKey& o : neighbourOffsets26()) {
      const VoxelKey m{k.x + o.x, k.y + o.y, k.z + o.z};
      if (!traversable(m)) continue;
      const double step = s_ * std::sqrt(static_cast<double>(o.x * o.x + o.y * o.y + o.z * o.z));
      auto [it, inserted] = nodes_.try_emplace(m, LatticeNode{g + step, k, false, true});
      if (!inserted) {
        if (it->second.closed || it->second.g <= g + step) continue;
        it->second.g = g + step;
        it->second.parent = k;
        it->second.has_parent = true;
      }
      open_.push({g + step + h(m), m});
    }
  }
  /// a, the lattice centres from a start node to `end`, then b.
  std::vector<Eigen::Vector3d> trace(VoxelKey end, const Eigen::Vector3d& a,
                                     const Eigen::Vector3d& b) const {
    std::vector<Eigen::Vector3d> path{b};
    for (VoxelKey k = end;;) {
      path.push_back(voxelCenter(k, s_));
      const LatticeNode& n = nodes_.at(k);
      if (!n.has_parent) break;
      k = n.parent;
    }
    path.push_back(a);
    std::reverse(path.begin(), path.end());
    return path;
  }

 private:
  using Item = std::pair<double, VoxelKey>;
  struct Later {
    bool operator()(const Item& x, const Item& y) const { return x.first > y.first; }
  };
  double s_;
  std::unordered_map<VoxelKey, LatticeNode, VoxelKeyHash> nodes_;
  std::priority_queue<Item, std::vector<Item>, Later> open_;
};

double polylineLength(const std::vector<Eigen::Vector3d>& path) {
  double len = 0.0;
  for (size_t i = 1; i < path.size(); ++i) len += (path[i] - path[i - 1]).norm();
  return len;
}

}  // namespace

void PathSearchConfig::validate() const {
  requireInRange("path.search_resolution_m", search_resolution_m, 0.05, 10.0);
  requireInRange("path.vehicle_radius_m", vehicle_radius_m, 0.0, 10.0);
  requireInRange("path.max_expansions", max_expansions, 1, 100000000);
  requireInRange("path.endpoint_tolerance_m", endpoint_tolerance_m, 0.0, 10.0);
}

PathSearch::PathSearch(const OccupancyMap& occ, PathSearchConfig config)
    : occ_(occ), config_(config) {
  config_.validate();
  memo_revision_ = occ_.revision();
}

bool PathSearch::traversable(const VoxelKey& k) {
  auto it = traversable_.find(k);
  if (it != traversable_.end()) return it->second;
  const bool ok = occ_.isSafe(center(k), config_.vehicle_radius_m, config_.unknown_is_traversable);
  traversable_.emplace(k, ok);
  return ok;
}

void PathSearch::syncMemo() {
  if (occ_.revision() != memo_revision_) {
    traversable_.clear();
    memo_revision_ = occ_.revision();
  }
}

void PathSearch::syncWithLastScan() {
  const uint64_t rev = occ_.revision();
  if (rev == memo_revision_) return;
  if (rev != memo_revision_ + 1) {
    syncMemo();
    return;
  }
  memo_revision_ = rev;
  if (traversable_.empty()) return;
  // A lattice node depends on the cells within the vehicle radius of its centre (and the
  // centre's cell): forget the nodes whose ball can reach a changed block.
  const double res = occ_.resolution();
  const double block_m = OccupancyMap::kBlockSize * res;
  const double grow = config_.vehicle_radius_m + res;
  const double s = config_.search_resolution_m;
  for (const VoxelKey& b : occ_.lastChangedBlocks()) {
    const Eigen::Vector3d lo =
        Eigen::Vector3d(b.x, b.y, b.z) * block_m - Eigen::Vector3d::Constant(grow);
    const Eigen::Vector3d hi = lo + Eigen::Vector3d::Constant(block_m + 2.0 * grow);
    const VoxelKey klo = toVoxelKey(lo, s), khi = toVoxelKey(hi, s);
    for (int32_t z = klo.z; z <= khi.z; ++z)
      for (int32_t y = klo.y; y <= khi.y; ++y)
        for (int32_t x = klo.x; x <= khi.x; ++x) traversable_.erase(VoxelKey{x, y, z});
  }
}

// End points join the lattice through one of the 27 nodes around them, by a segment that
// crosses no occupied cell (the end points themselves may sit closer to a wall than the
// vehicle radius, e.g. the robot after a tight turn).
std::vector<std::pair<VoxelKey, double>> PathSearch::attach(const Eigen::Vector3d& p) {
  std::vector<std::pair<VoxelKey, double>> out;
  const VoxelKey k0 = toVoxelKey(p, config_.search_resolution_m);
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const VoxelKey k{k0.x + dx, k0.y + dy, k0.z + dz};
        if (!traversable(k)) continue;
        if (!occ_.segmentSafe(p, center(k), 0.0, true)) continue;
        out.emplace_back(k, (center(k) - p).norm());
      }
  return out;
}

// Greedy string pulling: from each kept point jump to the farthest point still reachable by a
// safe straight segment. The end points keep the relaxed (radius 0) joining rule.
std::vector<Eigen::Vector3d> PathSearch::shorten(std::vector<Eigen::Vector3d> path) const {
  if (!config_.shorten || path.size() <= 2) return path;
  const double r = config_.vehicle_radius_m;
  const bool unk = config_.unknown_is_traversable;
  std::vector<Eigen::Vector3d> out{path.front()};
  size_t i = 0;
  while (i + 1 < path.size()) {
    size_t j = i + 1;
    for (size_t t = path.size() - 1; t > i + 1; --t) {
      const bool ends = (i == 0 || t == path.size() - 1);
      if (occ_.segmentSafe(path[i], path[t], ends ? 0.0 : r, ends ? true : unk)) {
        j = t;
        break;
      }
    }
    out.push_back(path[j]);
    i = j;
  }
  return out;
}

PathSearchResult PathSearch::search(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  PathSearchResult res;
  if (!a.allFinite() || !b.allFinite()) return res;
  syncMemo();
  if (occ_.segmentSafe(a, b, config_.vehicle_radius_m, config_.unknown_is_traversable)) {
    res.length_m = (b - a).norm();
    res.waypoints_world_m = {a, b};
    res.straight = true;
    return res;
  }
  const auto starts = attach(a);
  const auto goals = attach(b);
  if (starts.empty() || goals.empty()) return res;
  std::unordered_map<VoxelKey, double, VoxelKeyHash> goal_cost;
  for (const auto& [k, c] : goals) goal_cost[k] = c;

  Lattice lattice(config_.search_resolution_m);
  // f = g + h, where a goal node's h is its exact remaining cost; others use the straight line.
  auto h = [&](const VoxelKey& k) {
    auto it = goal_cost.find(k);
    const double straight = (center(k) - b).norm();
    return it == goal_cost.end() ? straight : std::min(straight, it->second);
  };
  auto trav = [this](const VoxelKey& k) { return traversable(k); };
  for (const auto& [k, c] : starts) lattice.seed(k, c, c + h(k));
  std::optional<VoxelKey> reached;
  double best_total = std::numeric_limits<double>::infinity();
  double f = 0.0;
  while (const auto top = lattice.pop(&f)) {
    if (f >= best_total) break;
    const auto [g, k] = *top;
    if (++res.expansions > config_.max_expansions) {
      res.budget_exhausted = true;
      break;
    }
    auto gc = goal_cost.find(k);
    if (gc != goal_cost.end() && g + gc->second < best_total) {
      best_total = g + gc->second;
      reached = k;
    }
    lattice.relax(k, g, trav, h);
  }
  if (!reached) return res;
  res.waypoints_world_m = shorten(lattice.trace(*reached, a, b));
  res.length_m = polylineLength(res.waypoints_world_m);
  return res;
}

std::vector<std::optional<double>> PathSearch::lengthsFrom(
    const Eigen::Vector3d& a, const std::vector<Eigen::Vector3d>& targets, int* expansions) {
  std::vector<std::optional<double>> out(targets.size());
  if (expansions) *expansions = 0;
  if (!a.allFinite()) return out;
  syncMemo();
  // Straight segments first; the others join the lattice (targets per attach node).
  std::unordered_map<VoxelKey, std::vector<std::pair<size_t, double>>, VoxelKeyHash> goal_nodes;
  for (size_t i = 0; i < targets.size(); ++i) {
    const Eigen::Vector3d& b = targets[i];
    if (!b.allFinite()) continue;
    if (occ_.segmentSafe(a, b, config_.vehicle_radius_m, config_.unknown_is_traversable)) {
      out[i] = (b - a).norm();
      continue;
    }
    for (const auto& [k, c] : attach(b)) goal_nodes[k].emplace_back(i, c);
  }
  if (goal_nodes.empty()) return out;
  const auto starts = attach(a);
  if (starts.empty()) return out;

  // Dijkstra from the source's attach nodes until every goal node is settled (or the budget
  // ends); each target keeps its best attach node.
  Lattice lattice(config_.search_resolution_m);
  for (const auto& [k, c] : starts) lattice.seed(k, c, c);
  std::vector<double> best(targets.size(), std::numeric_limits<double>::infinity());
  std::vector<std::optional<VoxelKey>> best_node(targets.size());
  size_t goals_left = goal_nodes.size();
  int expanded = 0;
  auto trav = [this](const VoxelKey& k) { return traversable(k); };
  auto zero = [](const VoxelKey&) { return 0.0; };
  while (goals_left > 0) {
    const auto top = lattice.pop(nullptr);
    if (!top || ++expanded > config_.max_expansions) break;
    const auto [g, k] = *top;
    if (auto gn = goal_nodes.find(k); gn != goal_nodes.end()) {
      --goals_left;
      for (const auto& [t, c] : gn->second)
        if (g + c < best[t]) {
          best[t] = g + c;
          best_node[t] = k;
        }
    }
    lattice.relax(k, g, trav, zero);
  }
  if (expansions) *expansions = expanded;
  for (size_t t = 0; t < targets.size(); ++t)
    if (!out[t] && best_node[t])
      out[t] = polylineLength(shorten(lattice.trace(*best_node[t], a, targets[t])));
  return out;
}

PathLengthCache::PathLengthCache(const OccupancyMap& occ, PathSearchConfig config)
    : occ_(occ), search_(occ, config), synced_revision_(occ.revision()) {}

std::optional<double> PathLengthCache::length(uint64_t id_a, const Eigen::Vector3d& a,
                                              uint64_t id_b, const Eigen::Vector3d& b) {
  const bool swap = id_b < id_a;
  const std::pair<uint64_t, uint64_t> key =
      swap ? std::make_pair(id_b, id_a) : std::make_pair(id_a, id_b);
  const Eigen::Vector3d& p = swap ? b : a;
  const Eigen::Vector3d& q = swap ? a : b;
  const double tol = search_.config().endpoint_tolerance_m;
  auto it = entries_.find(key);
  if (it != entries_.end() && (it->second.a - p).norm() <= tol &&
      (it->second.b - q).norm() <= tol) {
    ++stats_.hits;
    return it->second.length_m;
  }
  ++stats_.misses;
  const PathSearchResult r = search_.search(p, q);
  Entry e;
  e.a = p;
  e.b = q;
  e.length_m = r.length_m;
  VoxelKey lo = OccupancyMap::blockOf(occ_.key(p)), hi = lo;
  for (const Eigen::Vector3d& w : r.waypoints_world_m) {
    const VoxelKey bk = OccupancyMap::blockOf(occ_.key(w));
    lo = {std::min(lo.x, bk.x), std::min(lo.y, bk.y), std::min(lo.z, bk.z)};
    hi = {std::max(hi.x, bk.x), std::max(hi.y, bk.y), std::max(hi.z, bk.z)};
  }
  e.block_lo = {lo.x - 1, lo.y - 1, lo.z - 1};
  e.block_hi = {hi.x + 1, hi.y + 1, hi.z + 1};
  entries_[key] = e;
  return e.length_m;
}

void PathLengthCache::sync() {
  search_.syncWithLastScan();
  const uint64_t rev = occ_.revision();
  if (rev == synced_revision_) return;
  if (rev != synced_revision_ + 1) {
    stats_.invalidated += entries_.size();
    entries_.clear();
    synced_revision_ = rev;
    return;
  }
  synced_revision_ = rev;
  const auto& changed = occ_.lastChangedBlocks();
  const bool added_free = occ_.lastScanAddedFree();
  for (auto it = entries_.begin(); it != entries_.end();) {
    bool drop = !it->second.length_m.has_value() && added_free;
    if (!drop && it->second.length_m) {
      const Entry& e = it->second;
      for (const VoxelKey& c : changed) {
        if (c.x >= e.block_lo.x && c.x <= e.block_hi.x && c.y >= e.block_lo.y &&
            c.y <= e.block_hi.y && c.z >= e.block_lo.z && c.z <= e.block_hi.z) {
          drop = true;
          break;
        }
      }
    }
    if (drop) {
      ++stats_.invalidated;
      it = entries_.erase(it);
    } else {
      ++it;
    }
  }
}

void PathLengthCache::forget(uint64_t id) {
  for (auto it = entries_.begin(); it != entries_.end();) {
    if (it->first.first == id || it->first.second == id) {
      it = entries_.erase(it);
    } else {
      ++it;
    }
  }
}

}  // namespace efs::planner
