// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/observation_map.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <bitset>
#include <cmath>

#include "efs_common/config_check.h"
#include "efs_common/container_bytes.h"

namespace efs::planner {

void ObservationMapConfig::validate() const {
  requireInRange("observation.resolution_m", resolution_m, 0.02, 5.0);
  requirePositive("observation.max_range_m", max_range_m);
  requireInRange("observation.min_range_m", min_range_m, 0.0, max_range_m);
  requireInRange("observation.well_observed_distance_m", well_observed_distance_m, 0.0,
                 max_range_m);
  requireInRange("observation.min_view_directions", min_view_directions, 0,
                 ObservationMap::kNumDirectionBins);
  requireInRange("observation.direction_rule_max_distance_m", direction_rule_max_distance_m, 0.0,
                 max_range_m);
  requireInRange("observation.facing_max_distance_m", facing_max_distance_m, 0.0, max_range_m);
  requireInRange("observation.facing_min_cosine", facing_min_cosine, 0.0, 1.0);
}

const std::vector<VoxelKey>& neighbourOffsets26() {
  static const std::vector<VoxelKey> offsets = [] {
    std::vector<VoxelKey> o;
    for (int z = -1; z <= 1; ++z)
      for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
          if (x || y || z) o.push_back({x, y, z});
    return o;
  }();
  return offsets;
}

std::vector<VoxelKey> takeComponent26(const VoxelKey& seed,
                                      std::unordered_set<VoxelKey, VoxelKeyHash>& pending) {
  std::vector<VoxelKey> comp{seed};
  pending.erase(seed);
  for (size_t i = 0; i < comp.size(); ++i) {
    const VoxelKey k = comp[i];
    for (const VoxelKey& o : neighbourOffsets26()) {
      auto it = pending.find({k.x + o.x, k.y + o.y, k.z + o.z});
      if (it == pending.end()) continue;
      comp.push_back(*it);
      pending.erase(it);
    }
  }
  return comp;
}

ObservationMap::ObservationMap(ObservationMapConfig config) : config_(config) {
  config_.validate();
}

bool ObservationMap::isWellObservedRule(const ObservationMapConfig& c, double min_distance_m,
                                        uint32_t bins) {
  if (min_distance_m <= c.well_observed_distance_m) return true;
  return c.min_view_directions > 0 &&
         static_cast<int>(std::bitset<32>(bins).count()) >= c.min_view_directions;
}

int ObservationMap::directionBin(const Eigen::Vector3d& v) {
  constexpr double kPi = 3.14159265358979323846;
  const double az = std::atan2(v.y(), v.x());  // [-pi, pi]
  int a = static_cast<int>(std::floor((az + kPi) / (2.0 * kPi) * 8.0));
  if (a > 7) a = 7;
  if (a < 0) a = 0;
  const double horiz = std::hypot(v.x(), v.y());
  // Elevation bands split at +-30 deg: tan(30 deg) = 0.57735.
  const double t = v.z() / std::max(horiz, 1e-12);
  const int e = t < -0.5773502691896258 ? 0 : (t > 0.5773502691896258 ? 2 : 1);
  return e * 8 + a;
}

std::optional<Eigen::Vector3d> ObservationMap::surfaceNormal(const VoxelKey& k) const {
  constexpr int kMinCells = 5;
  Eigen::Vector3d pts[27];
  int n = 0;
  const auto add = [&](const VoxelKey& key) {
    auto it = cells_.find(key);
    if (it != cells_.end() && it->second.hits > 0)
      pts[n++] = (it->second.hit_sum_m / static_cast<float>(it->second.hits)).cast<double>();
  };
  add(k);
  for (const VoxelKey& o : neighbourOffsets26()) add({k.x + o.x, k.y + o.y, k.z + o.z});
  if (n < kMinCells) return std::nullopt;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) mean += pts[i];
  mean /= n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) cov += (pts[i] - mean) * (pts[i] - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(cov);
  const Eigen::Vector3d ev = es.eigenvalues();  // ascending
  // A plane: little spread across it, real spread along both of its axes (a line of cells or a
  // blob gives no normal to trust).
  if (!(ev(1) > 0.0) || ev(0) > 0.3 * ev(1)) return std::nullopt;
  return es.eigenvectors().col(0).normalized();
}

const SurfaceCell* ObservationMap::cell(const VoxelKey& k) const {
  auto it = cells_.find(k);
  return it == cells_.end() ? nullptr : &it->second;
}

bool ObservationMap::isWellObserved(const VoxelKey& k) const {
  const SurfaceCell* c = cell(k);
  return c && c->well_observed;
}

bool ObservationMap::hasWellNeighbour(const VoxelKey& k) const {
  for (const VoxelKey& o : neighbourOffsets26()) {
    auto it = cells_.find({k.x + o.x, k.y + o.y, k.z + o.z});
    if (it != cells_.end() && it->second.well_observed) return true;
  }
  return false;
}

void ObservationMap::setFrontier(const VoxelKey& k, SurfaceCell& c, bool frontier,
                                 ObservationUpdateStats& st) {
  if (c.frontier == frontier) return;
  c.frontier = frontier;
  if (frontier) {
    frontier_cells_.insert(k);
  } else {
    frontier_cells_.erase(k);
  }
  frontier_changes_.insert(k);
  ++st.frontier_changes;
}

ObservationUpdateStats ObservationMap::insertScan(const Eigen::Vector3d& origin,
                                                  const std::vector<Eigen::Vector3d>& points) {
  ObservationUpdateStats st;
  st.points_in = points.size();
  if (!origin.allFinite()) {
    st.rejected_scan = true;
    st.points_rejected_nonfinite = points.size();
    return st;
  }
  const double min_r2 = config_.min_range_m * config_.min_range_m;
  const double max_r2 = config_.max_range_m * config_.max_range_m;
  const double dir_r = config_.direction_rule_max_distance_m;
  const bool dir_rule = config_.min_view_directions > 0;
  const double facing_r = config_.facing_max_distance_m;
  std::vector<VoxelKey> fresh;        // new surface cells
  std::vector<VoxelKey> became_well;  // cells that turned well observed
  // Rule (c) needs the normal, which needs this scan's centroids: poorly observed cells seen
  // within facing_r, with the ray of their nearest point of this scan.
  std::unordered_map<VoxelKey, Eigen::Vector3d, VoxelKeyHash> facing_candidates;
  const auto markWell = [&](const VoxelKey& k, SurfaceCell& c) {
    c.well_observed = true;
    ++num_well_;
    columns_[{k.x, k.y, 0}] = 2;
    became_well.push_back(k);
  };
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite()) {
      ++st.points_rejected_nonfinite;
      continue;
    }
    const Eigen::Vector3d to_sensor = origin - p;
    const double r2 = to_sensor.squaredNorm();
    if (r2 < min_r2 || r2 > max_r2) {
      ++st.points_rejected_range;
      continue;
    }
    ++st.points_used;
    const VoxelKey k = key(p);
    auto [it, inserted] = cells_.try_emplace(k);
    SurfaceCell& c = it->second;
    if (inserted) {
      fresh.push_back(k);
      uint8_t& col = columns_[{k.x, k.y, 0}];
      if (col < 1) col = 1;
    }
    ++c.hits;
    c.hit_sum_m += p.cast<float>();
    if (c.well_observed) continue;
    const double r = std::sqrt(r2);
    if (r < c.min_distance_m) c.min_distance_m = static_cast<float>(r);
    if (dir_rule && r <= dir_r) c.view_direction_bins |= 1u << directionBin(to_sensor);
    if (isWellObservedRule(config_, c.min_distance_m, c.view_direction_bins)) {
      markWell(k, c);
    } else if (r <= facing_r) {
      auto [fit, first] = facing_candidates.try_emplace(k, to_sensor);
      if (!first && r2 < fit->second.squaredNorm()) fit->second = to_sensor;
    }
  }
  for (const auto& [k, to_sensor] : facing_candidates) {
    SurfaceCell& c = cells_[k];
    if (c.well_observed) continue;
    const std::optional<Eigen::Vector3d> n = surfaceNormal(k);
    if (n && std::abs(n->dot(to_sensor.normalized())) >= config_.facing_min_cosine) markWell(k, c);
  }
  st.new_cells = fresh.size();
  st.newly_well_observed = became_well.size();
  // Flags only move one way (poor -> well, never back), so these are the only updates needed:
  // a well observed cell is no frontier, its poorly observed neighbours are; a new poorly
  // observed cell is frontier when it touches a well observed one.
  for (const VoxelKey& k : became_well) {
    setFrontier(k, cells_[k], false, st);
    for (const VoxelKey& o : neighbourOffsets26()) {
      const VoxelKey n{k.x + o.x, k.y + o.y, k.z + o.z};
      auto it = cells_.find(n);
      if (it != cells_.end() && !it->second.well_observed) setFrontier(n, it->second, true, st);
    }
  }
  for (const VoxelKey& k : fresh) {
    SurfaceCell& c = cells_[k];
    if (!c.well_observed && !c.frontier && hasWellNeighbour(k)) setFrontier(k, c, true, st);
  }
  return st;
}

std::vector<VoxelKey> ObservationMap::takeFrontierChanges() {
  std::vector<VoxelKey> out(frontier_changes_.begin(), frontier_changes_.end());
  frontier_changes_.clear();
  return out;
}

void ObservationMap::countCellsNear(const Eigen::Vector3d& p, double radius_m, size_t* all,
                                    size_t* well) const {
  size_t n_all = 0, n_well = 0;
  const VoxelKey lo = key(p - Eigen::Vector3d::Constant(radius_m));
  const VoxelKey hi = key(p + Eigen::Vector3d::Constant(radius_m));
  const double r2 = radius_m * radius_m;
  const double cube_cells = double(hi.x - lo.x + 1) * (hi.y - lo.y + 1) * (hi.z - lo.z + 1);
  auto count = [&](const VoxelKey& k, const SurfaceCell& c) {
    if ((center(k) - p).squaredNorm() > r2) return;
    ++n_all;
    if (c.well_observed) ++n_well;
  };
  if (cube_cells > static_cast<double>(cells_.size())) {
    for (const auto& [k, c] : cells_) count(k, c);
  } else {
    for (int32_t z = lo.z; z <= hi.z; ++z)
      for (int32_t y = lo.y; y <= hi.y; ++y)
        for (int32_t x = lo.x; x <= hi.x; ++x) {
          auto it = cells_.find({x, y, z});
          if (it != cells_.end()) count(it->first, it->second);
        }
  }
  if (all) *all = n_all;
  if (well) *well = n_well;
}

int ObservationMap::bestLevelNear2d(const Eigen::Vector2d& c, double radius_m) const {
  const double res = config_.resolution_m;
  const int32_t x0 = static_cast<int32_t>(std::floor((c.x() - radius_m) / res));
  const int32_t x1 = static_cast<int32_t>(std::floor((c.x() + radius_m) / res));
  const int32_t y0 = static_cast<int32_t>(std::floor((c.y() - radius_m) / res));
  const int32_t y1 = static_cast<int32_t>(std::floor((c.y() + radius_m) / res));
  const double r2 = radius_m * radius_m;
  int best = 0;
  for (int32_t y = y0; y <= y1; ++y) {
    for (int32_t x = x0; x <= x1; ++x) {
      const double dx = (x + 0.5) * res - c.x(), dy = (y + 0.5) * res - c.y();
      if (dx * dx + dy * dy > r2) continue;
      auto it = columns_.find({x, y, 0});
      if (it == columns_.end()) continue;
      best = std::max<int>(best, it->second);
      if (best == 2) return 2;
    }
  }
  return best;
}

size_t ObservationMap::memoryBytes() const {
  return hashContainerBytes(cells_) + hashContainerBytes(columns_) +
         hashContainerBytes(frontier_cells_);
}

}  // namespace efs::planner
