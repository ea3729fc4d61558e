// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/path_length.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <queue>

#include "efs_common/config_check.h"
#include "efs_common/segment_distance.h"
#include "prior_guided_planner/observation_map.h"

namespace efs::planner {

void PathSearchConfig::validate() const {
  requireInRange("path.search_resolution_m", search_resolution_m, 0.05, 10.0);
  requireInRange("path.vehicle_radius_m", vehicle_radius_m, 0.0, 10.0);
  requireInRange("path.narrow_radius_m", narrow_radius_m, 0.0, vehicle_radius_m);
  requireInRange("path.narrow_cost_factor", narrow_cost_factor, 1.0, 100.0);
  requireInRange("path.max_expansions", max_expansions, 1, 100000000);
  requireInRange("path.endpoint_tolerance_m", endpoint_tolerance_m, 0.0, 10.0);
  requireInRange("path.shorten_lookahead_m", shorten_lookahead_m, search_resolution_m, 1e4);
}

namespace {

constexpr int kChunkBits = 3;
constexpr int kChunkSize = 1 << kChunkBits;
constexpr int kChunkNodes = kChunkSize * kChunkSize * kChunkSize;
constexpr uint8_t kNoParent = 255;

// A narrow node stores kNarrow + the index of its sub-point (0..7).
enum : uint8_t { kUntested = 0, kTraversable = 1, kBlocked = 2, kNarrow = 8 };

/// Sub-point i of a node: the centre of one octant of its cube.
Eigen::Vector3d subOffset(int i, double s) {
  return 0.25 * s *
         Eigen::Vector3d((i & 1) ? 1.0 : -1.0, (i & 2) ? 1.0 : -1.0, (i & 4) ? 1.0 : -1.0);
}

struct Offsets {
  VoxelKey d[26];
  double length[26];  ///< in lattice steps
};

const Offsets& offsets26() {
  static const Offsets o = [] {
    Offsets r;
    const auto& v = neighbourOffsets26();
    for (int i = 0; i < 26; ++i) {
      r.d[i] = v[i];
      r.length[i] =
          std::sqrt(static_cast<double>(v[i].x * v[i].x + v[i].y * v[i].y + v[i].z * v[i].z));
    }
    return r;
  }();
  return o;
}

struct QItem {
  double f;
  VoxelKey k;
  bool operator>(const QItem& o) const { return f > o.f; }
};
using OpenQueue = std::priority_queue<QItem, std::vector<QItem>, std::greater<QItem>>;

/// Whether some leg of the polyline passes within `reach` of p.
bool polylineWithin(const std::vector<Eigen::Vector3d>& w, const Eigen::Vector3d& p, double reach) {
  for (size_t i = 0; i + 1 < w.size(); ++i)
    if (efs::distanceToSegment<3>(p, w[i], w[i + 1]) <= reach) return true;
  return false;
}

double pathLength(const std::vector<Eigen::Vector3d>& path) {
  double len = 0.0;
  for (size_t i = 1; i < path.size(); ++i) len += (path[i] - path[i - 1]).norm();
  return len;
}

}  // namespace

// Flat per-node arrays of one 8^3 block of lattice nodes. Labels and search scratch carry an
// epoch per chunk and are reset lazily when a chunk is first touched in a newer epoch.
struct PathSearch::Chunk {
  uint8_t trav[kChunkNodes] = {};
  /// Per node, edges to its 26 neighbours known usable (bit d) / known unusable (bit d of the
  /// second word); only edges that touch a narrow node are ever tested. Reset with trav.
  uint32_t edge_ok[kChunkNodes] = {};
  uint32_t edge_bad[kChunkNodes] = {};
  uint32_t label[kChunkNodes];
  double g[kChunkNodes];
  uint8_t parent[kChunkNodes];
  uint8_t closed[kChunkNodes];
  uint32_t label_epoch = 0;
  uint32_t search_epoch = 0;
};

PathSearch::PathSearch(const OccupancyMap& occ, PathSearchConfig config)
    : occ_(occ), config_(config) {
  config_.validate();
  memo_revision_ = occ_.revision();
}

PathSearch::~PathSearch() = default;

inline PathSearch::Slot PathSearch::slot(const VoxelKey& k) {
  const VoxelKey ck{k.x >> kChunkBits, k.y >> kChunkBits, k.z >> kChunkBits};
  // Direct-mapped cache of recently used chunks (a node's neighbours span up to 8 chunks).
  const size_t line = static_cast<size_t>((ck.x & 3) | ((ck.y & 3) << 2) | ((ck.z & 1) << 4));
  ChunkCacheLine& cl = chunk_cache_[line];
  if (!cl.chunk || cl.key != ck) {
    auto& c = chunks_[ck];
    if (!c) c = std::make_unique<Chunk>();
    cl = {ck, c.get()};
  }
  const int m = kChunkSize - 1;
  return {cl.chunk, (k.x & m) | ((k.y & m) << kChunkBits) | ((k.z & m) << (2 * kChunkBits))};
}

inline bool PathSearch::traversable(const VoxelKey& k) { return traversable(slot(k), k); }

inline bool PathSearch::traversable(const Slot& s, const VoxelKey& k) {
  uint8_t& t = s.chunk->trav[s.index];
  if (t == kUntested) {
    const bool unk = config_.unknown_is_traversable;
    t = kBlocked;
    const Eigen::Vector3d c = center(k);
    if (occ_.isSafe(c, config_.vehicle_radius_m, unk)) {
      t = kTraversable;
    } else if (config_.narrow_radius_m > 0.0) {
      for (int i = 0; i < 8 && t == kBlocked; ++i)
        if (occ_.isSafe(c + subOffset(i, config_.search_resolution_m), config_.narrow_radius_m,
                        unk))
          t = static_cast<uint8_t>(kNarrow + i);
    }
  }
  return t == kTraversable || t >= kNarrow;
}

Eigen::Vector3d PathSearch::nodePosition(const Slot& s, const VoxelKey& k) const {
  const uint8_t t = s.chunk->trav[s.index];
  const Eigen::Vector3d c = center(k);
  return t >= kNarrow ? Eigen::Vector3d(c + subOffset(t - kNarrow, config_.search_resolution_m))
                      : c;
}

std::optional<double> PathSearch::edgeCost(const Slot& sa, const VoxelKey& a, const Slot& sb,
                                           const VoxelKey& b, int direction) const {
  const bool narrow = sa.chunk->trav[sa.index] >= kNarrow || sb.chunk->trav[sb.index] >= kNarrow;
  if (!narrow) return config_.search_resolution_m * offsets26().length[direction];
  const Eigen::Vector3d pa = nodePosition(sa, a), pb = nodePosition(sb, b);
  const uint32_t bit = 1u << direction;
  uint32_t& ok = sa.chunk->edge_ok[sa.index];
  uint32_t& bad = sa.chunk->edge_bad[sa.index];
  if (bad & bit) return std::nullopt;
  if (!(ok & bit)) {
    if (!segmentSafe(pa, pb, config_.narrow_radius_m, config_.unknown_is_traversable)) {
      bad |= bit;
      return std::nullopt;
    }
    ok |= bit;
  }
  return config_.narrow_cost_factor * (pb - pa).norm();
}

void PathSearch::clearMemo() {
  chunks_.clear();
  chunk_cache_.fill(ChunkCacheLine{});
  ++label_epoch_;
}

size_t PathSearch::memoSize() const {
  size_t n = 0;
  for (const auto& [key, c] : chunks_)
    for (uint8_t t : c->trav) n += t != kUntested;
  return n;
}

void PathSearch::ensureCurrent() {
  if (occ_.revision() == memo_revision_) return;
  clearMemo();
  memo_revision_ = occ_.revision();
}

void PathSearch::syncWithLastScan() {
  const uint64_t rev = occ_.revision();
  if (rev == memo_revision_) return;
  if (rev != memo_revision_ + 1) {
    ensureCurrent();
    return;
  }
  memo_revision_ = rev;
  if (occ_.lastChangesListed()) {
    syncWithChangedCells();
    return;
  }
  ++label_epoch_;  // any change may join or split components
  // A node's test reads the cells of its ball: retest the nodes whose centre lies within the
  // radius (plus a cell for rounding) of a changed block's box.
  const double s = config_.search_resolution_m;
  const double block_m = occ_.resolution() * OccupancyMap::kBlockSize;
  // A node's memoised edges reach its neighbours' sub-points: a diagonal step plus a quarter.
  const double edge_reach = config_.narrow_radius_m + 1.25 * std::sqrt(3.0) * s;
  const double grow = std::max(config_.vehicle_radius_m, edge_reach) + occ_.resolution();
  for (const VoxelKey& b : occ_.lastChangedBlocks()) {
    const Eigen::Vector3d lo =
        Eigen::Vector3d(b.x, b.y, b.z) * block_m - Eigen::Vector3d::Constant(grow);
    const Eigen::Vector3d hi =
        Eigen::Vector3d(b.x + 1, b.y + 1, b.z + 1) * block_m + Eigen::Vector3d::Constant(grow);
    forEachMemoisedNode(lo, hi, [](Chunk& c, int i, const VoxelKey&) {
      c.trav[i] = kUntested;
      c.edge_ok[i] = c.edge_bad[i] = 0;
    });
  }
}

template <typename F>
void PathSearch::forEachMemoisedNode(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, F&& f) {
  const double s = config_.search_resolution_m;
  const VoxelKey klo = toVoxelKey(lo, s), khi = toVoxelKey(hi, s);
  const int m = kChunkSize - 1;
  for (int32_t z = klo.z; z <= khi.z; ++z)
    for (int32_t y = klo.y; y <= khi.y; ++y)
      for (int32_t x = klo.x; x <= khi.x; ++x) {
        const auto it = chunks_.find({x >> kChunkBits, y >> kChunkBits, z >> kChunkBits});
        if (it == chunks_.end()) continue;
        const int i = (x & m) | ((y & m) << kChunkBits) | ((z & m) << (2 * kChunkBits));
        if (it->second->trav[i] != kUntested) f(*it->second, i, VoxelKey{x, y, z});
      }
}

// The few dozen cells a scan of a mapped place changes (surface cells a partly filled voxel
// keeps flipping) used to invalidate every node and every component label within metres of
// their blocks, so the next plan flood-filled the whole lattice again. Here the memoised nodes
// whose tests read a changed cell are tested again at once, the memoised narrow edges that pass
// near one are checked again, and the component labels are dropped only when an answer changed.
void PathSearch::syncWithChangedCells() {
  const double s = config_.search_resolution_m;
  const double half_cell = 0.5 * std::sqrt(3.0) * occ_.resolution();
  // A node's test reads the cells whose box meets its ball, or a narrow sub-point's ball.
  const double sub_reach =
      config_.narrow_radius_m > 0.0 ? config_.narrow_radius_m + 0.25 * std::sqrt(3.0) * s : 0.0;
  const double node_reach = std::max(config_.vehicle_radius_m, sub_reach) + half_cell;
  // A memoised edge joins two neighbours' positions (sub-points at most a quarter step out).
  const double edge_reach = config_.narrow_radius_m + 1.25 * std::sqrt(3.0) * s + half_cell;
  const Eigen::Vector3d node_grow = Eigen::Vector3d::Constant(node_reach);
  const Eigen::Vector3d edge_grow = Eigen::Vector3d::Constant(edge_reach);
  const auto& changes = occ_.lastChangedCells();
  bool changed = false;
  for (const CellChange& c : changes) {
    const Eigen::Vector3d p = occ_.center(c.cell);
    forEachMemoisedNode(p - node_grow, p + node_grow, [&](Chunk& ch, int i, const VoxelKey& k) {
      if ((center(k) - p).norm() > node_reach) return;
      const uint8_t before = ch.trav[i];
      ch.trav[i] = kUntested;
      traversable(Slot{&ch, i}, k);
      changed = changed || ch.trav[i] != before;
    });
  }
  if (changed) {
    // Positions moved or nodes came and went: the edges around are tested again when used.
    for (const CellChange& c : changes) {
      const Eigen::Vector3d p = occ_.center(c.cell);
      forEachMemoisedNode(p - edge_grow, p + edge_grow, [](Chunk& ch, int i, const VoxelKey&) {
        ch.edge_ok[i] = ch.edge_bad[i] = 0;
      });
    }
    ++label_epoch_;
    return;
  }
  const Offsets& o = offsets26();
  const double segment_reach = config_.narrow_radius_m + half_cell;
  for (const CellChange& c : changes) {
    const Eigen::Vector3d p = occ_.center(c.cell);
    forEachMemoisedNode(p - edge_grow, p + edge_grow, [&](Chunk& ch, int i, const VoxelKey& k) {
      const uint32_t memo = ch.edge_ok[i] | ch.edge_bad[i];
      if (!memo) return;
      const Slot sk{&ch, i};
      const Eigen::Vector3d pa = nodePosition(sk, k);
      for (int d = 0; d < 26; ++d) {
        const uint32_t bit = 1u << d;
        if (!(memo & bit)) continue;
        const VoxelKey n{k.x + o.d[d].x, k.y + o.d[d].y, k.z + o.d[d].z};
        const Eigen::Vector3d pb = nodePosition(slot(n), n);
        if (efs::distanceToSegment<3>(p, pa, pb) > segment_reach) continue;
        const bool ok =
            segmentSafe(pa, pb, config_.narrow_radius_m, config_.unknown_is_traversable);
        if (ok == static_cast<bool>(ch.edge_ok[i] & bit)) continue;
        ch.edge_ok[i] = ok ? (ch.edge_ok[i] | bit) : (ch.edge_ok[i] & ~bit);
        ch.edge_bad[i] = ok ? (ch.edge_bad[i] & ~bit) : (ch.edge_bad[i] | bit);
        changed = true;
      }
    });
  }
  if (changed) ++label_epoch_;
}

// Connected component of a traversable node (0 when blocked): flood fills the whole component
// the first time one of its nodes is asked in this label epoch.
uint32_t PathSearch::component(const VoxelKey& k) {
  if (!traversable(k)) return 0;
  auto labelRef = [&](const VoxelKey& n) -> uint32_t& {
    const Slot s = slot(n);
    if (s.chunk->label_epoch != label_epoch_) {
      std::fill(std::begin(s.chunk->label), std::end(s.chunk->label), 0u);
      s.chunk->label_epoch = label_epoch_;
    }
    return s.chunk->label[s.index];
  };
  if (const uint32_t l = labelRef(k)) return l;
  const uint32_t label = next_label_++;
  const Offsets& o = offsets26();
  std::vector<VoxelKey> stack{k};
  labelRef(k) = label;
  while (!stack.empty()) {
    const VoxelKey c = stack.back();
    stack.pop_back();
    const Slot sc = slot(c);
    for (int d = 0; d < 26; ++d) {
      const VoxelKey n{c.x + o.d[d].x, c.y + o.d[d].y, c.z + o.d[d].z};
      const Slot sn = slot(n);
      if (!traversable(sn, n)) continue;
      uint32_t& l = labelRef(n);
      if (l == label) continue;
      if (!edgeCost(sc, c, sn, n, d)) continue;
      l = label;
      stack.push_back(n);
    }
  }
  return label;
}

inline PathSearch::Slot PathSearch::scratch(const VoxelKey& k) {
  const Slot sl = slot(k);
  Chunk& c = *sl.chunk;
  if (c.search_epoch != search_epoch_) {
    std::fill(std::begin(c.g), std::end(c.g), std::numeric_limits<double>::infinity());
    std::fill(std::begin(c.closed), std::end(c.closed), uint8_t{0});
    c.search_epoch = search_epoch_;
  }
  return sl;
}

// OccupancyMap::segmentSafe with the same samples, visited every kStride-th first: a segment
// through a wall fails after a fraction of the samples (string pulling tries many of those).
bool PathSearch::segmentSafe(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_m,
                             bool unknown_is_safe) const {
  constexpr int kStride = 4;
  const double len = (b - a).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(len / (0.5 * occ_.resolution()))));
  auto safe = [&](int i) {
    return occ_.isSafe(a + (b - a) * (static_cast<double>(i) / n), radius_m, unknown_is_safe);
  };
  for (int i = 0; i <= n; i += kStride)
    if (!safe(i)) return false;
  for (int i = 0; i <= n; ++i)
    if (i % kStride != 0 && !safe(i)) return false;
  return true;
}

// End points join the lattice through one of the 27 nodes around them, by a segment that
// crosses no occupied cell (the end points themselves may sit closer to a wall than the
// vehicle radius, e.g. the robot after a tight turn).
PathSearch::Joins PathSearch::attach(const Eigen::Vector3d& p) {
  Joins out;
  const VoxelKey k0 = toVoxelKey(p, config_.search_resolution_m);
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const VoxelKey k{k0.x + dx, k0.y + dy, k0.z + dz};
        const Slot sk = slot(k);
        if (!traversable(sk, k)) continue;
        const Eigen::Vector3d q = nodePosition(sk, k);
        if (!segmentSafe(p, q, 0.0, true)) continue;
        out.emplace_back(k, (q - p).norm());
      }
  return out;
}

struct PathSearch::SegmentMemo {
  struct Query {
    Eigen::Vector3d a, b;
    double radius_m;
    bool unknown_is_safe;
    bool operator==(const Query& o) const {
      return a == o.a && b == o.b && radius_m == o.radius_m && unknown_is_safe == o.unknown_is_safe;
    }
  };
  struct QueryHash {
    size_t operator()(const Query& q) const noexcept {
      uint64_t h = q.unknown_is_safe ? 1u : 0u;
      const auto mix = [&h](double v) {
        uint64_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        h = (h ^ bits) * 0x9E3779B97F4A7C15ULL;
        h ^= h >> 29;
      };
      for (int i = 0; i < 3; ++i) mix(q.a[i]), mix(q.b[i]);
      mix(q.radius_m);
      return static_cast<size_t>(h);
    }
  };
  /// search.segmentSafe for `q`, tested on the first ask only.
  bool safe(const PathSearch& search, const Query& q) {
    const auto [it, first_ask] = answers.try_emplace(q, false);
    if (first_ask) it->second = search.segmentSafe(q.a, q.b, q.radius_m, q.unknown_is_safe);
    return it->second;
  }
  std::unordered_map<Query, bool, QueryHash> answers;
};

// Greedy string pulling: from each kept point jump to the farthest point within
// shorten_lookahead_m along the path still reachable by a safe straight segment. The end points
// keep the relaxed (radius 0) joining rule.
std::vector<Eigen::Vector3d> PathSearch::shorten(std::vector<Eigen::Vector3d> path,
                                                 SegmentMemo* memo) const {
  if (!config_.shorten || path.size() <= 2) return path;
  const double r = config_.vehicle_radius_m;
  const bool unk = config_.unknown_is_traversable;
  // along[k]: length of the lattice path up to node k.
  std::vector<double> along(path.size(), 0.0);
  for (size_t k = 1; k < path.size(); ++k) along[k] = along[k - 1] + (path[k] - path[k - 1]).norm();
  std::vector<Eigen::Vector3d> out{path.front()};
  size_t i = 0;
  while (i + 1 < path.size()) {
    size_t j = i + 1;
    const size_t last = static_cast<size_t>(
        std::upper_bound(along.begin(), along.end(), along[i] + config_.shorten_lookahead_m) -
        along.begin() - 1);
    for (size_t t = std::max(last, i + 1); t > i + 1; --t) {
      const bool ends = (i == 0 || t == path.size() - 1);
      const SegmentMemo::Query q{path[i], path[t], ends ? 0.0 : r, ends ? true : unk};
      if (memo ? memo->safe(*this, q) : segmentSafe(q.a, q.b, q.radius_m, q.unknown_is_safe)) {
        j = t;
        break;
      }
    }
    out.push_back(path[j]);
    i = j;
  }
  return out;
}

// a, the lattice nodes from a start node to `last` (parents of the current search), b;
// shortened.
std::vector<Eigen::Vector3d> PathSearch::tracePath(const Eigen::Vector3d& a, const VoxelKey& last,
                                                   const Eigen::Vector3d& b, SegmentMemo* memo) {
  const Offsets& o = offsets26();
  std::vector<Eigen::Vector3d> path{b};
  for (VoxelKey k = last;;) {
    const Slot s = slot(k);
    path.push_back(nodePosition(s, k));
    const uint8_t p = s.chunk->parent[s.index];
    if (p == kNoParent) break;
    k = {k.x - o.d[p].x, k.y - o.d[p].y, k.z - o.d[p].z};
  }
  path.push_back(a);
  std::reverse(path.begin(), path.end());
  return shorten(std::move(path), memo);
}

namespace {

// Keeps the joins whose component is in `labels`.
template <typename Joins, typename Label>
Joins keepLabelled(const Joins& joins, const std::vector<uint32_t>& labels, Label&& label) {
  Joins out;
  for (const auto& j : joins)
    if (std::find(labels.begin(), labels.end(), label(j.first)) != labels.end()) out.push_back(j);
  return out;
}

}  // namespace

// Best-first expansion over the lattice from the join nodes `starts` (cost = their join
// length) with priority g + h. `stop(f)` ends the search before the node of priority f is
// closed; `visit(k, g)` sees each closed node. Parents are left in the search scratch.
template <typename Heuristic, typename Stop, typename Visit>
PathSearch::SearchStats PathSearch::bestFirst(const Joins& starts, Heuristic&& h, Stop&& stop,
                                              Visit&& visit) {
  ++search_epoch_;
  SearchStats st;
  OpenQueue open;
  for (const auto& [k, c] : starts) {
    const Slot sl = scratch(k);
    if (sl.chunk->g[sl.index] <= c) continue;
    sl.chunk->g[sl.index] = c;
    sl.chunk->parent[sl.index] = kNoParent;
    open.push({c + h(k), k});
  }
  const Offsets& o = offsets26();
  while (!open.empty()) {
    const QItem top = open.top();
    open.pop();
    if (stop(top.f)) break;
    const VoxelKey k = top.k;
    const Slot sl = scratch(k);
    if (sl.chunk->closed[sl.index]) continue;
    sl.chunk->closed[sl.index] = 1;
    if (++st.expansions > config_.max_expansions) {
      st.exhausted = true;
      break;
    }
    const double g = sl.chunk->g[sl.index];
    visit(k, g);
    for (int d = 0; d < 26; ++d) {
      const VoxelKey m{k.x + o.d[d].x, k.y + o.d[d].y, k.z + o.d[d].z};
      const Slot sm = scratch(m);
      if (!traversable(sm, m) || sm.chunk->closed[sm.index]) continue;
      if (wide_only_ && sm.chunk->trav[sm.index] != kTraversable) continue;
      const std::optional<double> cost = edgeCost(sl, k, sm, m, d);
      if (!cost) continue;
      const double gm = g + *cost;
      if (sm.chunk->g[sm.index] <= gm) continue;
      sm.chunk->g[sm.index] = gm;
      sm.chunk->parent[sm.index] = static_cast<uint8_t>(d);
      open.push({gm + h(m), m});
    }
  }
  return st;
}

bool PathSearch::connected(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (!a.allFinite() || !b.allFinite()) return false;
  ensureCurrent();
  if (segmentSafe(a, b, config_.vehicle_radius_m, config_.unknown_is_traversable)) return true;
  std::vector<uint32_t> la;
  for (const auto& [k, c] : attach(a)) la.push_back(component(k));
  for (const auto& [k, c] : attach(b))
    if (std::find(la.begin(), la.end(), component(k)) != la.end()) return true;
  return false;
}

PathSearchResult PathSearch::search(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  PathSearchResult res;
  if (!a.allFinite() || !b.allFinite()) return res;
  ensureCurrent();
  const double r = config_.vehicle_radius_m;
  const bool unk = config_.unknown_is_traversable;
  if (segmentSafe(a, b, r, unk)) {
    res.length_m = (b - a).norm();
    res.waypoints_world_m = {a, b};
    res.straight = true;
    return res;
  }
  auto label = [&](const VoxelKey& k) { return component(k); };
  const Joins all_goals = attach(b);
  std::vector<uint32_t> goal_labels;
  for (const auto& j : all_goals) goal_labels.push_back(component(j.first));
  const Joins all_starts = keepLabelled(attach(a), goal_labels, label);
  if (all_starts.empty()) return res;
  std::vector<uint32_t> start_labels;
  for (const auto& j : all_starts) start_labels.push_back(component(j.first));
  const Joins all_goals_reachable = keepLabelled(all_goals, start_labels, label);

  // Wide nodes first; narrow ones only when that finds nothing (a door): in open space the
  // shell of narrow nodes along the walls would only cost expansions.
  for (const bool wide_only : {true, false}) {
    if (!wide_only && config_.narrow_radius_m <= 0.0) break;
    const Joins starts = wide_only ? wideJoins(all_starts) : all_starts;
    const Joins goals = wide_only ? wideJoins(all_goals_reachable) : all_goals_reachable;
    if (starts.empty() || goals.empty()) continue;
    // f = g + h, where a goal node's h is its exact remaining cost; others the straight line.
    auto goalCost = [&](const VoxelKey& k) {
      double best = std::numeric_limits<double>::infinity();
      for (const auto& [gk, c] : goals)
        if (gk == k) best = std::min(best, c);
      return best;
    };
    auto h = [&](const VoxelKey& k) {
      return std::min((nodePosition(slot(k), k) - b).norm(), goalCost(k));
    };
    std::optional<VoxelKey> reached;
    double best_total = std::numeric_limits<double>::infinity();
    wide_only_ = wide_only;
    const SearchStats st = bestFirst(
        starts, h, [&](double f) { return f >= best_total; },
        [&](const VoxelKey& k, double g) {
          const double gc = goalCost(k);
          if (g + gc < best_total) {
            best_total = g + gc;
            reached = k;
          }
        });
    wide_only_ = false;
    res.expansions += st.expansions;
    res.budget_exhausted = st.exhausted;
    if (!reached) continue;
    res.waypoints_world_m = tracePath(a, *reached, b);
    res.length_m = pathLength(res.waypoints_world_m);
    return res;
  }
  return res;
}

PathSearch::Joins PathSearch::wideJoins(const Joins& joins) {
  Joins out;
  for (const auto& j : joins)
    if (slot(j.first).chunk->trav[slot(j.first).index] == kTraversable) out.push_back(j);
  return out;
}

std::vector<PathSearchResult> PathSearch::searchFrom(const Eigen::Vector3d& a,
                                                     const std::vector<Eigen::Vector3d>& targets) {
  std::vector<PathSearchResult> out(targets.size());
  if (!a.allFinite()) return out;
  ensureCurrent();
  const double r = config_.vehicle_radius_m;
  const bool unk = config_.unknown_is_traversable;
  const Joins starts = attach(a);
  std::vector<uint32_t> start_labels;
  for (const auto& j : starts) start_labels.push_back(component(j.first));
  // Straight segments first; the others join the lattice in the robot's components.
  std::vector<std::pair<VoxelKey, std::pair<int, double>>> goal_joins;
  for (size_t i = 0; i < targets.size(); ++i) {
    const Eigen::Vector3d& b = targets[i];
    if (!b.allFinite()) continue;
    if (segmentSafe(a, b, r, unk)) {
      out[i].length_m = (b - a).norm();
      out[i].waypoints_world_m = {a, b};
      out[i].straight = true;
      continue;
    }
    for (const auto& [k, c] : attach(b))
      if (std::find(start_labels.begin(), start_labels.end(), component(k)) != start_labels.end())
        goal_joins.push_back({k, {static_cast<int>(i), c}});
  }
  std::sort(goal_joins.begin(), goal_joins.end(),
            [](const auto& x, const auto& y) { return voxelKeyLess(x.first, y.first); });

  // Dijkstra from the start nodes until every goal node is settled (or the budget ends); each
  // target keeps its best join node. Over wide nodes first; the targets that stay unreached get
  // a second Dijkstra that may cross narrow nodes (doors), as search() does.
  std::vector<bool> pending(targets.size(), false);
  for (const auto& gj : goal_joins) pending[gj.second.first] = true;
  SegmentMemo memo;
  for (const bool wide_only : {true, false}) {
    if (!wide_only && config_.narrow_radius_m <= 0.0) break;
    std::vector<std::pair<VoxelKey, std::pair<int, double>>> goals;
    for (const auto& gj : goal_joins) {
      if (!pending[gj.second.first]) continue;
      const Slot sg = slot(gj.first);
      if (wide_only && sg.chunk->trav[sg.index] != kTraversable) continue;
      goals.push_back(gj);
    }
    const Joins phase_starts = wide_only ? wideJoins(starts) : starts;
    if (goals.empty() || phase_starts.empty()) continue;
    size_t goals_left = 0;
    for (size_t i = 0; i < goals.size(); ++i)
      goals_left += i == 0 || goals[i].first != goals[i - 1].first;
    std::vector<double> best(targets.size(), std::numeric_limits<double>::infinity());
    std::vector<std::optional<VoxelKey>> best_node(targets.size());
    wide_only_ = wide_only;
    const SearchStats st = bestFirst(
        phase_starts, [](const VoxelKey&) { return 0.0; }, [&](double) { return goals_left == 0; },
        [&](const VoxelKey& k, double g) {
          auto lo = std::lower_bound(
              goals.begin(), goals.end(), k,
              [&](const auto& gj, const VoxelKey& key) { return voxelKeyLess(gj.first, key); });
          if (lo == goals.end() || lo->first != k) return;
          --goals_left;
          for (; lo != goals.end() && lo->first == k; ++lo) {
            const auto [t, c] = lo->second;
            if (g + c < best[t]) {
              best[t] = g + c;
              best_node[t] = k;
            }
          }
        });
    wide_only_ = false;
    for (size_t t = 0; t < targets.size(); ++t) {
      if (!pending[t]) continue;
      out[t].expansions += st.expansions;
      if (!best_node[t]) {
        out[t].budget_exhausted = st.exhausted;
        continue;
      }
      // Traced now: the next phase's search reuses the scratch that holds the parents.
      out[t].waypoints_world_m = tracePath(a, *best_node[t], targets[t], &memo);
      out[t].length_m = pathLength(out[t].waypoints_world_m);
      pending[t] = false;
    }
  }
  return out;
}

std::vector<std::optional<double>> PathSearch::lengthsFrom(
    const Eigen::Vector3d& a, const std::vector<Eigen::Vector3d>& targets, int* expansions) {
  const std::vector<PathSearchResult> found = searchFrom(a, targets);
  std::vector<std::optional<double>> out;
  out.reserve(found.size());
  int expanded = 0;
  for (const PathSearchResult& r : found) {
    out.push_back(r.length_m);
    expanded = std::max(expanded, r.expansions);
  }
  if (expansions) *expansions = expanded;
  return out;
}

PathLengthCache::PathLengthCache(const OccupancyMap& occ, PathSearchConfig config)
    : occ_(occ), search_(occ, config), synced_revision_(occ.revision()) {}

namespace {

std::pair<uint64_t, uint64_t> orderedKey(uint64_t id_a, uint64_t id_b) {
  return id_b < id_a ? std::make_pair(id_b, id_a) : std::make_pair(id_a, id_b);
}

}  // namespace

const PathLengthCache::Entry* PathLengthCache::valid(uint64_t id_a, const Eigen::Vector3d& a,
                                                     uint64_t id_b,
                                                     const Eigen::Vector3d& b) const {
  const bool swap = id_b < id_a;
  const Eigen::Vector3d& p = swap ? b : a;
  const Eigen::Vector3d& q = swap ? a : b;
  const double tol = search_.config().endpoint_tolerance_m;
  auto it = entries_.find(orderedKey(id_a, id_b));
  if (it == entries_.end() || (it->second.a - p).norm() > tol || (it->second.b - q).norm() > tol)
    return nullptr;
  return &it->second;
}

void PathLengthCache::store(uint64_t id_a, const Eigen::Vector3d& a, uint64_t id_b,
                            const Eigen::Vector3d& b, PathSearchResult r) {
  const bool swap = id_b < id_a;
  Entry e;
  e.a = swap ? b : a;
  e.b = swap ? a : b;
  e.length_m = r.length_m;
  e.path_world_m = std::move(r.waypoints_world_m);
  VoxelKey lo = OccupancyMap::blockOf(occ_.key(a)), hi = lo;
  for (const Eigen::Vector3d& w : e.path_world_m) {
    const VoxelKey bk = OccupancyMap::blockOf(occ_.key(w));
    lo = {std::min(lo.x, bk.x), std::min(lo.y, bk.y), std::min(lo.z, bk.z)};
    hi = {std::max(hi.x, bk.x), std::max(hi.y, bk.y), std::max(hi.z, bk.z)};
  }
  e.block_lo = {lo.x - 1, lo.y - 1, lo.z - 1};
  e.block_hi = {hi.x + 1, hi.y + 1, hi.z + 1};
  // Cells that can matter lie within the shortcut reach of pathNear (cells) of the path.
  const int grow = static_cast<int>(std::ceil(
                       (search_.config().vehicle_radius_m + search_.config().search_resolution_m) /
                       occ_.resolution())) +
                   1;
  VoxelKey clo = occ_.key(a), chi = clo;
  for (const Eigen::Vector3d& w : e.path_world_m) {
    const VoxelKey k = occ_.key(w);
    clo = {std::min(clo.x, k.x), std::min(clo.y, k.y), std::min(clo.z, k.z)};
    chi = {std::max(chi.x, k.x), std::max(chi.y, k.y), std::max(chi.z, k.z)};
  }
  e.cell_lo = {clo.x - grow, clo.y - grow, clo.z - grow};
  e.cell_hi = {chi.x + grow, chi.y + grow, chi.z + grow};
  entries_[orderedKey(id_a, id_b)] = std::move(e);
}

std::optional<double> PathLengthCache::length(uint64_t id_a, const Eigen::Vector3d& a,
                                              uint64_t id_b, const Eigen::Vector3d& b) {
  nodes_[id_a] = {a, scans_};
  nodes_[id_b] = {b, scans_};
  if (const Entry* e = valid(id_a, a, id_b, b)) {
    ++stats_.hits;
    return e->length_m;
  }
  ++stats_.misses;
  std::vector<uint64_t> ids;
  std::vector<Eigen::Vector3d> targets;
  for (const auto& [id_c, n] : nodes_)
    if (id_c != id_a && id_c != id_b && n.last_asked_scan + kBatchScans >= scans_ &&
        !valid(id_a, a, id_c, n.position_world_m)) {
      ids.push_back(id_c);
      targets.push_back(n.position_world_m);
    }
  if (ids.size() + 1 < kMinBatch) {
    PathSearchResult r = search_.search(a, b);
    const std::optional<double> l = r.length_m;
    store(id_a, a, id_b, b, std::move(r));
    return l;
  }
  ++stats_.batch_searches;
  ids.push_back(id_b);
  targets.push_back(b);
  std::vector<PathSearchResult> found = search_.searchFrom(a, targets);
  const std::optional<double> l = found.back().length_m;
  for (size_t i = 0; i < ids.size(); ++i) store(id_a, a, ids[i], targets[i], std::move(found[i]));
  return l;
}

std::vector<Eigen::Vector3d> PathLengthCache::path(uint64_t id_a, const Eigen::Vector3d& a,
                                                   uint64_t id_b, const Eigen::Vector3d& b) {
  if (!length(id_a, a, id_b, b)) return {};
  const Entry* e = valid(id_a, a, id_b, b);
  if (!e) return {};
  std::vector<Eigen::Vector3d> out = e->path_world_m;
  // An entry keeps its path in the direction it was searched, from either end.
  if (!out.empty() && (out.front() - a).squaredNorm() > (out.front() - b).squaredNorm())
    std::reverse(out.begin(), out.end());
  return out;
}

// Whether a changed block (its centre, grown by half its diagonal) comes within the vehicle
// radius plus one lattice step of a leg of the entry's path.
bool PathLengthCache::pathNear(const Entry& e, const std::vector<VoxelKey>& blocks) const {
  const double block_m = occ_.resolution() * OccupancyMap::kBlockSize;
  const double reach = search_.config().vehicle_radius_m + search_.config().search_resolution_m +
                       0.5 * std::sqrt(3.0) * block_m;
  const std::vector<Eigen::Vector3d>& w = e.path_world_m;
  for (const VoxelKey& c : blocks) {
    if (c.x < e.block_lo.x || c.x > e.block_hi.x || c.y < e.block_lo.y || c.y > e.block_hi.y ||
        c.z < e.block_lo.z || c.z > e.block_hi.z)
      continue;
    const Eigen::Vector3d m =
        (Eigen::Vector3d(c.x, c.y, c.z) + Eigen::Vector3d::Constant(0.5)) * block_m;
    if (polylineWithin(w, m, reach)) return true;
  }
  return false;
}

// Whether a changed cell can matter to the entry's path: a cell that turned occupied within the
// vehicle radius of a leg may block it; one that turned free within the radius plus a lattice
// step may open a shortcut (the same reach as the block test, at the cell's own place).
bool PathLengthCache::pathNear(const Entry& e, const std::vector<CellChange>& cells) const {
  const double half_cell = 0.5 * std::sqrt(3.0) * occ_.resolution();
  const double block_reach = search_.config().vehicle_radius_m + half_cell;
  const double open_reach = block_reach + search_.config().search_resolution_m;
  const std::vector<Eigen::Vector3d>& w = e.path_world_m;
  for (const CellChange& c : cells) {
    if (c.cell.x < e.cell_lo.x || c.cell.x > e.cell_hi.x || c.cell.y < e.cell_lo.y ||
        c.cell.y > e.cell_hi.y || c.cell.z < e.cell_lo.z || c.cell.z > e.cell_hi.z)
      continue;
    const double reach = c.after == OccupancyState::kOccupied ? block_reach : open_reach;
    if (polylineWithin(w, occ_.center(c.cell), reach)) return true;
  }
  return false;
}

void PathLengthCache::sync() {
  ++scans_;
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
  const bool listed = occ_.lastChangesListed();
  const bool added_free = occ_.lastScanAddedFree();
  for (auto it = entries_.begin(); it != entries_.end();) {
    const Entry& e = it->second;
    const bool drop = !e.length_m ? added_free
                      : listed    ? pathNear(e, occ_.lastChangedCells())
                                  : pathNear(e, changed);
    if (drop) {
      ++stats_.invalidated;
      it = entries_.erase(it);
    } else {
      ++it;
    }
  }
}

void PathLengthCache::forget(uint64_t id) {
  nodes_.erase(id);
  for (auto it = entries_.begin(); it != entries_.end();) {
    if (it->first.first == id || it->first.second == id) {
      it = entries_.erase(it);
    } else {
      ++it;
    }
  }
}

}  // namespace efs::planner
