// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/occupancy_map.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "efs_common/config_check.h"

namespace efs::planner {

void OccupancyConfig::validate() const {
  requireInRange("occupancy.resolution_m", resolution_m, 0.02, 5.0);
  requirePositive("occupancy.max_range_m", max_range_m);
  requireInRange("occupancy.min_range_m", min_range_m, 0.0, max_range_m);
  // Log-odds are stored as int8 in steps of 0.05: +-6.35 is the representable span.
  requireInRange("occupancy.log_odds_hit", log_odds_hit, 0.05, 6.0);
  requireInRange("occupancy.log_odds_miss", log_odds_miss, -6.0, -0.05);
  requireInRange("occupancy.log_odds_miss_occupied", log_odds_miss_occupied, -6.0, -0.05);
  requireInRange("occupancy.log_odds_min", log_odds_min, -6.3, 0.0);
  requireInRange("occupancy.log_odds_max", log_odds_max, 0.0, 6.3);
  requireInRange("occupancy.log_odds_occupied", log_odds_occupied, log_odds_min, log_odds_max);
}

OccupancyMap::OccupancyMap(OccupancyConfig config) : config_(config) {
  config_.validate();
  auto q = [](double v) { return static_cast<int>(std::lround(v / kQuantum)); };
  hit_q_ = q(config_.log_odds_hit);
  miss_q_ = q(config_.log_odds_miss);
  miss_occupied_q_ = q(config_.log_odds_miss_occupied);
  min_q_ = q(config_.log_odds_min);
  max_q_ = q(config_.log_odds_max);
  occupied_q_ = q(config_.log_odds_occupied);
}

OccupancyMap::Block* OccupancyMap::findBlock(const VoxelKey& block_key) const {
  const std::optional<size_t> i = block_index_.find(block_key);
  return i ? blocks_[*i].get() : nullptr;
}

OccupancyMap::Block& OccupancyMap::touchBlock(const VoxelKey& block_key) {
  const size_t i = block_index_.insert(block_key);
  if (i == blocks_.size()) blocks_.push_back(std::make_unique<Block>());
  return *blocks_[i];
}

void OccupancyMap::updateCell(Block& b, const VoxelKey& block_key, const VoxelKey& cell, bool hit) {
  Cell& c = b.cells[localIndex(cell)];
  if (c.stamp == scan_stamp_) return;  // once per scan; hits were applied first, so they win
  c.stamp = scan_stamp_;
  const OccupancyState before = classify(c.log_odds);
  int v = c.log_odds == kUnknownValue ? 0 : c.log_odds;
  if (before == OccupancyState::kUnknown) ++known_cells_;
  const int miss = before == OccupancyState::kOccupied ? miss_occupied_q_ : miss_q_;
  v = std::clamp(v + (hit ? hit_q_ : miss), min_q_, max_q_);
  c.log_odds = static_cast<int8_t>(v);
  const OccupancyState after = classify(c.log_odds);
  if (after != before) {
    if (after == OccupancyState::kFree) last_added_free_ = true;
    if (after == OccupancyState::kOccupied) last_added_occupied_ = true;
    if (changes_listed_) {
      if (changed_cells_.size() < kMaxListedChanges) {
        changed_cells_.push_back({cell, before, after});
      } else {
        changes_listed_ = false;
        changed_cells_.clear();
      }
    }
    if (b.changed_stamp != scan_stamp_) {
      b.changed_stamp = scan_stamp_;
      changed_blocks_.push_back(block_key);
    }
  }
}

OccupancyUpdateStats OccupancyMap::insertScan(const Eigen::Vector3d& origin,
                                              const std::vector<Eigen::Vector3d>& points) {
  OccupancyUpdateStats st;
  st.points_in = points.size();
  changed_blocks_.clear();
  changed_cells_.clear();
  changes_listed_ = true;
  last_added_free_ = last_added_occupied_ = false;
  if (!origin.allFinite()) {
    st.rejected_scan = true;
    st.points_rejected_nonfinite = points.size();
    return st;
  }
  scan_stamp_ = static_cast<uint8_t>(scan_stamp_ == 255 ? 1 : scan_stamp_ + 1);
  const double res = config_.resolution_m;
  const double min_r2 = config_.min_range_m * config_.min_range_m;
  const double max_r = config_.max_range_m;

  // Pass 1: hits. The first point to land in a cell this scan defines that cell's ray; later
  // points in the same cell would clear the same cells again.
  std::vector<Eigen::Vector3d> ray_ends;
  ray_ends.reserve(points.size());
  VoxelKey cached_bk{INT32_MIN, INT32_MIN, INT32_MIN};
  Block* cached_b = nullptr;
  auto blockFor = [&](const VoxelKey& cell) -> std::pair<Block*, VoxelKey> {
    const VoxelKey bk = blockOf(cell);
    if (bk != cached_bk || !cached_b) {
      cached_bk = bk;
      cached_b = &touchBlock(bk);
    }
    return {cached_b, bk};
  };
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) {
      ++st.points_rejected_nonfinite;
      continue;
    }
    const Eigen::Vector3d d = p - origin;
    const double r2 = d.squaredNorm();
    if (r2 < min_r2) {
      ++st.points_rejected_too_close;
      continue;
    }
    if (r2 > max_r * max_r) {
      ++st.points_clipped;
      ray_ends.push_back(origin + d * (max_r / std::sqrt(r2)));
      continue;
    }
    const VoxelKey k = key(p);
    auto [b, bk] = blockFor(k);
    if (b->cells[localIndex(k)].stamp == scan_stamp_) continue;
    updateCell(*b, bk, k, true);
    ray_ends.push_back(p);
  }
  // Pass 2: misses along each ray, end cell excluded. A clipped ray's end cell is free too.
  for (const Eigen::Vector3d& e : ray_ends) {
    ++st.rays_cast;
    forEachCellOnSegment(origin, e, res, [&](const VoxelKey& k) {
      ++st.cells_traversed;
      auto [b, bk] = blockFor(k);
      updateCell(*b, bk, k, false);
      return true;
    });
  }
  st.blocks_changed = changed_blocks_.size();
  if (!changed_blocks_.empty()) ++revision_;
  return st;
}

OccupancyState OccupancyMap::state(const VoxelKey& k) const { return Cursor(*this).state(k); }

bool OccupancyMap::isSafe(const Eigen::Vector3d& p, double radius_m, bool unknown_is_safe) const {
  const OccupancyState c = stateAt(p);
  if (c == OccupancyState::kOccupied) return false;
  if (c == OccupancyState::kUnknown && !unknown_is_safe) return false;
  return allCellsInBall(p, radius_m,
                        [](OccupancyState s) { return s != OccupancyState::kOccupied; });
}

bool OccupancyMap::isKnownFree(const Eigen::Vector3d& p, double radius_m) const {
  return allCellsInBall(p, radius_m, [](OccupancyState s) { return s == OccupancyState::kFree; });
}

bool OccupancyMap::allCellsInBall(const Eigen::Vector3d& p, double radius_m,
                                  bool (*ok)(OccupancyState)) const {
  const double res = config_.resolution_m;
  Cursor cur(*this);
  const VoxelKey lo = key(p - Eigen::Vector3d::Constant(radius_m));
  const VoxelKey hi = key(p + Eigen::Vector3d::Constant(radius_m));
  const double r2 = radius_m * radius_m;
  for (int32_t z = lo.z; z <= hi.z; ++z) {
    const double dz = std::max({z * res - p.z(), 0.0, p.z() - (z + 1) * res});
    for (int32_t y = lo.y; y <= hi.y; ++y) {
      const double dy = std::max({y * res - p.y(), 0.0, p.y() - (y + 1) * res});
      const double dyz2 = dy * dy + dz * dz;
      if (dyz2 > r2) continue;
      for (int32_t x = lo.x; x <= hi.x; ++x) {
        const double dx = std::max({x * res - p.x(), 0.0, p.x() - (x + 1) * res});
        if (dx * dx + dyz2 > r2) continue;  // the cell's box is outside the ball
        if (!ok(classify(cur.value({x, y, z})))) return false;
      }
    }
  }
  return true;
}

bool OccupancyMap::segmentSafe(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_m,
                               bool unknown_is_safe) const {
  const double len = (b - a).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(len / (0.5 * config_.resolution_m))));
  for (int i = 0; i <= n; ++i) {
    if (!isSafe(a + (b - a) * (static_cast<double>(i) / n), radius_m, unknown_is_safe))
      return false;
  }
  return true;
}

bool OccupancyMap::lineOfSight(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                               bool unknown_blocks, int ignore_near_to_cells) const {
  Cursor cur(*this);
  const VoxelKey k_from = key(from);
  const VoxelKey k_to = key(to);
  const int n = ignore_near_to_cells;
  return forEachCellOnSegment(from, to, config_.resolution_m, [&](const VoxelKey& k) {
    if (k == k_from) return true;
    if (std::abs(k.x - k_to.x) <= n && std::abs(k.y - k_to.y) <= n && std::abs(k.z - k_to.z) <= n)
      return true;
    const OccupancyState s = classify(cur.value(k));
    if (s == OccupancyState::kOccupied) return false;
    return !(unknown_blocks && s == OccupancyState::kUnknown);
  });
}

size_t OccupancyMap::memoryBytes() const {
  return block_index_.memoryBytes() + blocks_.capacity() * sizeof(std::unique_ptr<Block>) +
         blocks_.size() * sizeof(Block);
}

}  // namespace efs::planner
