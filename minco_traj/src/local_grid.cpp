// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/local_grid.h"

#include <algorithm>
#include <cmath>

#include "efs_common/config_check.h"

namespace efs::traj {

void LocalGridConfig::validate() const {
  requireInRange("local_grid.resolution_m", resolution_m, 0.02, 2.0);
  requireInRange("local_grid.size_x_m", size_x_m, 4 * resolution_m, 200.0);
  requireInRange("local_grid.size_y_m", size_y_m, 4 * resolution_m, 200.0);
  requireInRange("local_grid.size_z_m", size_z_m, 4 * resolution_m, 100.0);
  const double cells =
      (size_x_m / resolution_m) * (size_y_m / resolution_m) * (size_z_m / resolution_m);
  requireThat(cells <= 64e6, "local_grid.size_x_m",
              "window has more than 64 million cells; enlarge resolution_m or shrink the window");
  requireInRange("local_grid.inflation_radius_m", inflation_radius_m, 0.0, 3.0);
  requireInRange("local_grid.narrow_radius_m", narrow_radius_m, 0.0, 3.0);
  requireInRange("local_grid.memory_radius_m", memory_radius_m, 0.0, 100000.0);
  requirePositive("local_grid.max_ray_length_m", max_ray_length_m);
  requireInRange("local_grid.ray_downsample_m", ray_downsample_m, 0.0, 5.0);
  requireInRange("local_grid.logodds_hit", logodds_hit, 1e-3, 10.0);
  requireInRange("local_grid.logodds_miss", logodds_miss, -10.0, -1e-3);
  requireInRange("local_grid.logodds_miss_occupied", logodds_miss_occupied, -10.0, -1e-3);
  requireInRange("local_grid.logodds_min", logodds_min, -20.0,
                 std::min(logodds_miss, logodds_miss_occupied));
  requireInRange("local_grid.logodds_max", logodds_max, logodds_hit, 20.0);
  requireInRange("local_grid.logodds_occupied", logodds_occupied, logodds_min, logodds_max);
}

const char* toString(CellState s) {
  switch (s) {
    case CellState::kUnknown:
      return "unknown";
    case CellState::kFree:
      return "free";
    case CellState::kOccupied:
      return "occupied";
    case CellState::kOutside:
      return "outside";
  }
  return "?";
}

LocalGrid::LocalGrid(const LocalGridConfig& cfg, const Eigen::Vector3d& c) : cfg_(cfg) {
  cfg_.validate();
  nx_ = static_cast<int>(std::ceil(cfg_.size_x_m / cfg_.resolution_m - 1e-6));
  ny_ = static_cast<int>(std::ceil(cfg_.size_y_m / cfg_.resolution_m - 1e-6));
  nz_ = static_cast<int>(std::ceil(cfg_.size_z_m / cfg_.resolution_m - 1e-6));
  const size_t n = static_cast<size_t>(nx_) * ny_ * nz_;
  logodds_.assign(n, 0.f);
  observed_.assign(n, 0);
  occupied_.assign(n, 0);
  inflation_.assign(n, 0);
  // At or above the inflation radius the inflation itself answers (isBlocked).
  if (cfg_.narrow_radius_m > 0.0 && cfg_.narrow_radius_m < cfg_.inflation_radius_m)
    narrow_inflation_.assign(n, 0);
  scan_stamp_.assign(n, 0);
  const VoxelKey ck = key(c);
  min_key_ = {ck.x - nx_ / 2, ck.y - ny_ / 2, ck.z - nz_ / 2};
  const int r = static_cast<int>(std::ceil(cfg_.inflation_radius_m / cfg_.resolution_m));
  const double r2 = std::pow(cfg_.inflation_radius_m / cfg_.resolution_m, 2) + 1e-9;
  for (int dx = -r; dx <= r; ++dx)
    for (int dy = -r; dy <= r; ++dy)
      for (int dz = -r; dz <= r; ++dz)
        if (dx * dx + dy * dy + dz * dz <= r2) kernel_.push_back({dx, dy, dz});
  const auto sq = [](const VoxelKey& o) { return o.x * o.x + o.y * o.y + o.z * o.z; };
  std::stable_sort(kernel_.begin(), kernel_.end(),
                   [&](const VoxelKey& a, const VoxelKey& b) { return sq(a) < sq(b); });
  const double nr2 = std::pow(cfg_.narrow_radius_m / cfg_.resolution_m, 2) + 1e-9;
  if (!narrow_inflation_.empty())
    while (narrow_kernel_size_ < kernel_.size() && sq(kernel_[narrow_kernel_size_]) <= nr2)
      ++narrow_kernel_size_;
}

Eigen::Vector3d LocalGrid::windowMin() const {
  return Eigen::Vector3d(min_key_.x, min_key_.y, min_key_.z) * cfg_.resolution_m;
}
Eigen::Vector3d LocalGrid::windowMax() const {
  return Eigen::Vector3d(min_key_.x + nx_, min_key_.y + ny_, min_key_.z + nz_) * cfg_.resolution_m;
}

namespace {
// Key held by each slot along one axis for a window starting at min_key (slot = key mod n).
std::vector<int> slotKeys(int min_key, int n) {
  std::vector<int> keys(n);
  for (int i = 0; i < n; ++i) {
    const int r = (i - min_key) % n;
    keys[i] = min_key + (r < 0 ? r + n : r);
  }
  return keys;
}
}  // namespace

void LocalGrid::recenter(const Eigen::Vector3d& c) {
  const VoxelKey ck = key(c);
  const VoxelKey new_min{ck.x - nx_ / 2, ck.y - ny_ / 2, ck.z - nz_ / 2};
  if (new_min == min_key_) return;
  const VoxelKey old_min = min_key_;
  min_key_ = new_min;
  // Each slot holds the unique key of the old window congruent to it; forget it if that key left.
  auto leaving = [](int old_lo, int new_lo, int n) {
    std::vector<uint8_t> out(n);
    const std::vector<int> keys = slotKeys(old_lo, n);
    for (int i = 0; i < n; ++i) out[i] = keys[i] < new_lo || keys[i] >= new_lo + n;
    return out;
  };
  const auto out_x = leaving(old_min.x, new_min.x, nx_);
  const auto out_y = leaving(old_min.y, new_min.y, ny_);
  const auto out_z = leaving(old_min.z, new_min.z, nz_);
  const bool keep = cfg_.memory_radius_m > 0.0;
  const std::vector<int> kx = slotKeys(old_min.x, nx_), ky = slotKeys(old_min.y, ny_),
                         kz = slotKeys(old_min.z, nz_);
  size_t idx = 0;
  for (int ix = 0; ix < nx_; ++ix)
    for (int iy = 0; iy < ny_; ++iy)
      for (int iz = 0; iz < nz_; ++iz, ++idx)
        if (out_x[ix] || out_y[iy] || out_z[iz]) {
          if (keep && occupied_[idx]) remember({kx[ix], ky[iy], kz[iz]}, logodds_[idx]);
          logodds_[idx] = 0.f;
          observed_[idx] = 0;
          occupied_[idx] = 0;
        }
  if (keep) {
    cropMemory();
    restoreRemembered();
  }
  recomputeInflation();
}

void LocalGrid::remember(const VoxelKey& k, float logodds) {
  memory_[memoryBlock(k)].push_back({k, logodds});
  ++remembered_;
}

void LocalGrid::restoreRemembered() {
  const VoxelKey lo = memoryBlock(min_key_), hi = memoryBlock(maxKey());
  for (int32_t bx = lo.x; bx <= hi.x; ++bx)
    for (int32_t by = lo.y; by <= hi.y; ++by)
      for (int32_t bz = lo.z; bz <= hi.z; ++bz) {
        const auto it = memory_.find({bx, by, bz});
        if (it == memory_.end()) continue;
        std::vector<RememberedCell>& cells = it->second;
        size_t kept = 0;
        for (const RememberedCell& c : cells) {
          if (!inWindow(c.key)) {
            cells[kept++] = c;
            continue;
          }
          const size_t i = index(c.key);
          logodds_[i] = c.logodds;
          observed_[i] = 1;
          occupied_[i] = 1;
        }
        remembered_ -= cells.size() - kept;
        cells.resize(kept);
        if (cells.empty()) memory_.erase(it);
      }
}

void LocalGrid::cropMemory() {
  const Eigen::Vector3d c = 0.5 * (windowMin() + windowMax());
  const double block_m = cfg_.resolution_m * (1 << kMemoryBlockBits);
  const double r = cfg_.memory_radius_m + block_m;  // block centre to its farthest cell
  for (auto it = memory_.begin(); it != memory_.end();) {
    const Eigen::Vector2d b((it->first.x + 0.5) * block_m, (it->first.y + 0.5) * block_m);
    if ((b - c.head<2>()).squaredNorm() > r * r) {
      remembered_ -= it->second.size();
      it = memory_.erase(it);
    } else {
      ++it;
    }
  }
}

void LocalGrid::recomputeInflation() {
  std::fill(inflation_.begin(), inflation_.end(), 0);
  std::fill(narrow_inflation_.begin(), narrow_inflation_.end(), 0);
  // Sequential pass over the slots; keys only for the (few) occupied ones.
  const std::vector<int> kx = slotKeys(min_key_.x, nx_), ky = slotKeys(min_key_.y, ny_),
                         kz = slotKeys(min_key_.z, nz_);
  size_t idx = 0;
  for (int ix = 0; ix < nx_; ++ix)
    for (int iy = 0; iy < ny_; ++iy)
      for (int iz = 0; iz < nz_; ++iz, ++idx)
        if (occupied_[idx]) stampInflation({kx[ix], ky[iy], kz[iz]}, +1);
}

void LocalGrid::stampInflation(const VoxelKey& k, int sign) {
  const auto bump = [sign](uint16_t& c) {
    c = static_cast<uint16_t>(sign > 0 ? c + 1 : (c > 0 ? c - 1 : 0));
  };
  const bool narrow = !narrow_inflation_.empty();
  for (size_t i = 0; i < kernel_.size(); ++i) {
    const VoxelKey& o = kernel_[i];
    const VoxelKey n{k.x + o.x, k.y + o.y, k.z + o.z};
    if (!inWindow(n)) continue;
    const size_t idx = index(n);
    bump(inflation_[idx]);
    if (narrow && i < narrow_kernel_size_) bump(narrow_inflation_[idx]);
  }
}

void LocalGrid::updateCell(size_t idx, const VoxelKey& k, float delta) {
  const bool was_occ = observed_[idx] && logodds_[idx] > cfg_.logodds_occupied;
  observed_[idx] = 1;
  logodds_[idx] = std::clamp(logodds_[idx] + delta, static_cast<float>(cfg_.logodds_min),
                             static_cast<float>(cfg_.logodds_max));
  const bool is_occ = logodds_[idx] > cfg_.logodds_occupied;
  occupied_[idx] = is_occ;
  if (is_occ != was_occ) stampInflation(k, is_occ ? +1 : -1);
}

void LocalGrid::insertScan(const Eigen::Vector3d& origin,
                           const std::vector<Eigen::Vector3d>& points) {
  if (++scan_id_ == 0) {  // wrapped: reset stamps so that old ones cannot collide
    std::fill(scan_stamp_.begin(), scan_stamp_.end(), 0);
    scan_id_ = 1;
  }
  const double res = cfg_.resolution_m;
  // Hits first, so that a cell hit in this scan is not cleared by a grazing ray of the same scan.
  for (const auto& p : points) {
    if (!p.allFinite() || (p - origin).norm() > cfg_.max_ray_length_m) continue;
    const VoxelKey k = key(p);
    if (!inWindow(k)) continue;
    const size_t idx = index(k);
    if (scan_stamp_[idx] == scan_id_) continue;
    scan_stamp_[idx] = scan_id_;
    float delta = static_cast<float>(cfg_.logodds_hit);
    if (cfg_.hit_overrides_free) {
      delta = std::max(
          delta, static_cast<float>(cfg_.logodds_occupied + cfg_.logodds_hit) - logodds_[idx]);
    }
    updateCell(idx, k, delta);
  }
  // One ray per coarse end voxel (the first point in it), in a deterministic order.
  ray_bins_.clear();
  for (uint32_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    uint64_t bin = i;
    if (cfg_.ray_downsample_m > 0.0) {
      const VoxelKey c = toVoxelKey(points[i], cfg_.ray_downsample_m);
      bin = (static_cast<uint64_t>(c.x & 0x1fffff) << 42) |
            (static_cast<uint64_t>(c.y & 0x1fffff) << 21) | static_cast<uint64_t>(c.z & 0x1fffff);
    }
    ray_bins_.emplace_back(bin, i);
  }
  std::sort(ray_bins_.begin(), ray_bins_.end());
  for (size_t r = 0; r < ray_bins_.size(); ++r) {
    if (r > 0 && ray_bins_[r].first == ray_bins_[r - 1].first) continue;
    const Eigen::Vector3d& p = points[ray_bins_[r].second];
    Eigen::Vector3d end = p;
    const double len = (p - origin).norm();
    if (len > cfg_.max_ray_length_m) end = origin + (p - origin) * (cfg_.max_ray_length_m / len);
    const VoxelKey end_key = key(end);
    traverseCells(origin, end, res, [&](const VoxelKey& k) {
      if (k == end_key) return false;
      if (!inWindow(k)) return true;  // the origin may be outside; keep walking inwards
      const size_t idx = index(k);
      if (scan_stamp_[idx] == scan_id_) return true;
      scan_stamp_[idx] = scan_id_;
      updateCell(
          idx, k,
          static_cast<float>(occupied_[idx] ? cfg_.logodds_miss_occupied : cfg_.logodds_miss));
      return true;
    });
  }
}

void LocalGrid::setOccupied(const Eigen::Vector3d& p) {
  const VoxelKey k = key(p);
  if (!inWindow(k)) return;
  const size_t idx = index(k);
  updateCell(idx, k, static_cast<float>(cfg_.logodds_max - logodds_[idx]));
}

void LocalGrid::setFree(const Eigen::Vector3d& p) {
  const VoxelKey k = key(p);
  if (!inWindow(k)) return;
  const size_t idx = index(k);
  updateCell(idx, k, static_cast<float>(cfg_.logodds_min - logodds_[idx]));
}

void LocalGrid::setAllFree() {
  std::fill(logodds_.begin(), logodds_.end(), static_cast<float>(cfg_.logodds_min));
  std::fill(observed_.begin(), observed_.end(), 1);
  std::fill(occupied_.begin(), occupied_.end(), 0);
  std::fill(inflation_.begin(), inflation_.end(), 0);
  std::fill(narrow_inflation_.begin(), narrow_inflation_.end(), 0);
}

CellState LocalGrid::state(const VoxelKey& k) const {
  if (!inWindow(k)) return CellState::kOutside;
  const size_t idx = index(k);
  if (!observed_[idx]) return CellState::kUnknown;
  return logodds_[idx] > cfg_.logodds_occupied ? CellState::kOccupied : CellState::kFree;
}

bool LocalGrid::isInflated(const VoxelKey& k) const {
  return inWindow(k) && inflation_[index(k)] > 0;
}

bool LocalGrid::isBlocked(const VoxelKey& k, bool unknown_is_free,
                          double narrow_clearance_m) const {
  if (!inWindow(k)) return true;
  const size_t idx = index(k);
  if (inflation_[idx] > 0) {
    if (narrow_clearance_m <= 0.0 || narrow_clearance_m >= cfg_.inflation_radius_m ||
        occupied_[idx])
      return true;
    if (!narrow_inflation_.empty() && std::abs(narrow_clearance_m - cfg_.narrow_radius_m) < 1e-9) {
      if (narrow_inflation_[idx] > 0) return true;
    } else if (nearestOccupiedDistance(center(k), narrow_clearance_m)) {
      return true;
    }
  }
  return !unknown_is_free && !observed_[idx];
}

bool LocalGrid::isInterior(const VoxelKey& k) const {
  static const int kOff[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                 {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  for (const auto& o : kOff) {
    const VoxelKey n{k.x + o[0], k.y + o[1], k.z + o[2]};
    if (!inWindow(n) || !occupied_[index(n)]) return false;
  }
  return true;
}

void LocalGrid::occupiedCentersInBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                     std::vector<Eigen::Vector3d>& out, bool surface_only) const {
  const double res = cfg_.resolution_m;
  const VoxelKey wmax = maxKey();
  const int x0 = std::max(min_key_.x, static_cast<int>(std::ceil(lo.x() / res - 0.5)));
  const int y0 = std::max(min_key_.y, static_cast<int>(std::ceil(lo.y() / res - 0.5)));
  const int z0 = std::max(min_key_.z, static_cast<int>(std::ceil(lo.z() / res - 0.5)));
  const int x1 = std::min(wmax.x, static_cast<int>(std::floor(hi.x() / res - 0.5)));
  const int y1 = std::min(wmax.y, static_cast<int>(std::floor(hi.y() / res - 0.5)));
  const int z1 = std::min(wmax.z, static_cast<int>(std::floor(hi.z() / res - 0.5)));
  if (z1 < z0) return;
  const int iz0 = posMod(z0, nz_);
  for (int x = x0; x <= x1; ++x)
    for (int y = y0; y <= y1; ++y) {
      const size_t base = (static_cast<size_t>(posMod(x, nx_)) * ny_ + posMod(y, ny_)) * nz_;
      int iz = iz0;
      for (int z = z0; z <= z1; ++z) {
        if (occupied_[base + iz]) {
          const VoxelKey k{x, y, z};
          if (!surface_only || !isInterior(k)) out.push_back(center(k));
        }
        if (++iz == nz_) iz = 0;
      }
    }
}

std::optional<double> LocalGrid::nearestOccupiedDistance(const Eigen::Vector3d& p,
                                                         double radius_m) const {
  const int r = static_cast<int>(std::ceil(radius_m / cfg_.resolution_m));
  const VoxelKey c = key(p);
  double best_sq = radius_m * radius_m;
  bool found = false;
  for (int dx = -r; dx <= r; ++dx)
    for (int dy = -r; dy <= r; ++dy)
      for (int dz = -r; dz <= r; ++dz) {
        const VoxelKey k{c.x + dx, c.y + dy, c.z + dz};
        if (!inWindow(k) || !occupied_[index(k)]) continue;
        const double d_sq = (center(k) - p).squaredNorm();
        if (d_sq <= best_sq) {
          best_sq = d_sq;
          found = true;
        }
      }
  if (!found) return std::nullopt;
  return std::sqrt(best_sq);
}

size_t LocalGrid::occupiedCount() const {
  size_t n = 0;
  for (uint8_t o : occupied_) n += o;
  return n;
}

}  // namespace efs::traj
