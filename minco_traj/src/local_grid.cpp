// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/local_grid.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "efs_common/config_check.h"
#include "efs_common/container_bytes.h"

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
  cells_.assign(n, Cell{});
  settled_free_.assign((n + 63) / 64, 0);
  // At or above the inflation radius the inflation itself answers (isBlocked).
  has_narrow_ = cfg_.narrow_radius_m > 0.0 && cfg_.narrow_radius_m < cfg_.inflation_radius_m;
  const VoxelKey ck = key(c);
  setWindow({ck.x - nx_ / 2, ck.y - ny_ / 2, ck.z - nz_ / 2});
  const double r_cells = cfg_.inflation_radius_m / cfg_.resolution_m;
  const double r2 = r_cells * r_cells + 1e-9;
  const double nr = !has_narrow_ ? -1.0 : cfg_.narrow_radius_m / cfg_.resolution_m;
  const double nr2 = nr < 0.0 ? -1.0 : nr * nr + 1e-9;
  kernel_reach_ = static_cast<int>(std::ceil(r_cells));
  const auto half_height = [](double radius2, int planar2) {
    if (radius2 < planar2) return -1;
    int h = static_cast<int>(std::floor(std::sqrt(radius2 - planar2)));
    // Guard the square root's rounding both ways: h is the largest with planar2 + h^2 <= r^2.
    while (h > 0 && planar2 + h * h > radius2) --h;
    while (planar2 + (h + 1) * (h + 1) <= radius2) ++h;
    return h;
  };
  for (int dx = -kernel_reach_; dx <= kernel_reach_; ++dx)
    for (int dy = -kernel_reach_; dy <= kernel_reach_; ++dy) {
      const int planar2 = dx * dx + dy * dy;
      const int h = half_height(r2, planar2);
      if (h >= 0) kernel_.push_back({dx, dy, h, half_height(nr2, planar2)});
    }
  const size_t span = 2 * kernel_reach_ + 1;
  stamp_slots_x_.resize(span);
  stamp_slots_y_.resize(span);
  stamp_slots_z_.resize(span);
}

void LocalGrid::setWindow(const VoxelKey& min_key) {
  min_key_ = min_key;
  phase_ = {posMod(min_key.x, nx_), posMod(min_key.y, ny_), posMod(min_key.z, nz_)};
}

Eigen::Vector3d LocalGrid::windowMin() const {
  return Eigen::Vector3d(min_key_.x, min_key_.y, min_key_.z) * cfg_.resolution_m;
}
Eigen::Vector3d LocalGrid::windowMax() const {
  return Eigen::Vector3d(min_key_.x + nx_, min_key_.y + ny_, min_key_.z + nz_) * cfg_.resolution_m;
}

namespace {
/// Parameter interval [t0, t1] of from + t (to - from), t in [0, 1], inside the box; empty
/// (t0 > t1) when the segment misses it.
std::pair<double, double> clipSegment(const Eigen::Vector3d& from, const Eigen::Vector3d& to,
                                      const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector3d d = to - from;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (from[a] < lo[a] || from[a] > hi[a]) return {1.0, 0.0};
      continue;
    }
    double ta = (lo[a] - from[a]) / d[a], tb = (hi[a] - from[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return {t0, t1};
}

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
  // The key each slot holds in the old window, and per slot and axis whether it leaves: a slot's
  // key leaves on some axis exactly when the slot's new key enters on it.
  const std::vector<int> kx = slotKeys(old_min.x, nx_), ky = slotKeys(old_min.y, ny_),
                         kz = slotKeys(old_min.z, nz_);
  auto changing = [](const std::vector<int>& keys, int new_lo, int n) {
    std::vector<uint8_t> out(n);
    for (int i = 0; i < n; ++i) out[i] = keys[i] < new_lo || keys[i] >= new_lo + n;
    return out;
  };
  const auto ch_x = changing(kx, new_min.x, nx_);
  const auto ch_y = changing(ky, new_min.y, ny_);
  const auto ch_z = changing(kz, new_min.z, nz_);
  const bool all_change = std::all_of(ch_x.begin(), ch_x.end(), [](uint8_t b) { return b; }) ||
                          std::all_of(ch_y.begin(), ch_y.end(), [](uint8_t b) { return b; }) ||
                          std::all_of(ch_z.begin(), ch_z.end(), [](uint8_t b) { return b; });
  const bool keep = cfg_.memory_radius_m > 0.0;
  // The inflation is kept across the move rather than computed again over the window: a move of
  // recenter_distance_m touches a slab of the window, and the window's occupied surface stamped
  // anew cost some 30 ms per move (traj_bench). Occupied cells that leave take their stamps off
  // the cells that stay, before the window moves (their keys are those of the old window).
  if (!all_change)
    forEachChangingSlot(ch_x, ch_y, ch_z, [&](size_t idx, int ix, int iy, int iz) {
      if (cells_[idx].occupied) stampInflation({kx[ix], ky[iy], kz[iz]}, -1);
    });
  forEachChangingSlot(ch_x, ch_y, ch_z, [&](size_t idx, int ix, int iy, int iz) {
    Cell& cell = cells_[idx];
    if (keep && cell.occupied) remember({kx[ix], ky[iy], kz[iz]}, cell.logodds);
    cell = Cell{};
    setSettledFree(idx, false);
  });
  setWindow(new_min);
  // Occupied cells that stay, within the ball's reach of the entering slots, stamp those slots;
  // remembered cells coming back stamp every cell around them (restoreRemembered).
  if (!all_change) {
    const std::vector<int> nkx = slotKeys(new_min.x, nx_), nky = slotKeys(new_min.y, ny_),
                           nkz = slotKeys(new_min.z, nz_);
    auto nearEntering = [this](const std::vector<uint8_t>& entering, int n) {
      std::vector<uint8_t> near(n, 0);
      for (int i = 0; i < n; ++i)
        if (entering[i])
          for (int o = -kernel_reach_; o <= kernel_reach_; ++o) near[posMod(i + o, n)] = 1;
      return near;
    };
    // Slot neighbours are key neighbours but for the window's two ends, which meet in the ring
    // buffer: marking across them only adds cells to look at, never misses one.
    const auto near_x = nearEntering(ch_x, nx_), near_y = nearEntering(ch_y, ny_),
               near_z = nearEntering(ch_z, nz_);
    const EnteringSlots entering{ch_x.data(), ch_y.data(), ch_z.data()};
    forEachChangingSlot(near_x, near_y, near_z, [&](size_t idx, int ix, int iy, int iz) {
      if (ch_x[ix] || ch_y[iy] || ch_z[iz] || !cells_[idx].occupied) return;
      stampInflation({nkx[ix], nky[iy], nkz[iz]}, +1, &entering);
    });
  }
  if (keep) {
    cropMemory();
    restoreRemembered();
  }
}

template <typename Visit>
void LocalGrid::forEachChangingSlot(const std::vector<uint8_t>& ch_x,
                                    const std::vector<uint8_t>& ch_y,
                                    const std::vector<uint8_t>& ch_z, Visit&& visit) const {
  // The slots flagged on some axis: whole y-z planes, whole z columns, then single cells.
  std::vector<int> z_slots;
  for (int iz = 0; iz < nz_; ++iz)
    if (ch_z[iz]) z_slots.push_back(iz);
  for (int ix = 0; ix < nx_; ++ix)
    for (int iy = 0; iy < ny_; ++iy) {
      const size_t column = (static_cast<size_t>(ix) * ny_ + iy) * nz_;
      if (ch_x[ix] || ch_y[iy]) {
        for (int iz = 0; iz < nz_; ++iz) visit(column + iz, ix, iy, iz);
      } else {
        for (int iz : z_slots) visit(column + iz, ix, iy, iz);
      }
    }
}

void LocalGrid::rememberHitAboveOrBelow(const VoxelKey& k, float logodds) {
  if (!inWindowXY(k)) return;
  const VoxelKey block = memoryBlock(k);
  const RememberedCell cell = packRemembered(k, block, logodds);
  std::vector<RememberedCell>& cells = memory_[block];
  for (RememberedCell& c : cells)
    if (c.x == cell.x && c.y == cell.y && c.z == cell.z) {
      c.logodds_q = std::max(c.logodds_q, cell.logodds_q);
      return;
    }
  cells.push_back(cell);
  ++remembered_;
}

float LocalGrid::hitDelta(float logodds) const {
  const float hit = static_cast<float>(cfg_.logodds_hit);
  return cfg_.hit_overrides_free
             ? std::max(hit, static_cast<float>(cfg_.logodds_occupied + cfg_.logodds_hit) - logodds)
             : hit;
}

void LocalGrid::remember(const VoxelKey& k, float logodds) {
  const VoxelKey block = memoryBlock(k);
  memory_[block].push_back(packRemembered(k, block, logodds));
  ++remembered_;
}

LocalGrid::RememberedCell LocalGrid::packRemembered(const VoxelKey& k, const VoxelKey& block,
                                                    float logodds) const {
  const VoxelKey base = rememberedKey({0, 0, 0, 0}, block);
  const double q = std::ceil((logodds - cfg_.logodds_min) / rememberedLogoddsStep());
  return {static_cast<uint8_t>(k.x - base.x), static_cast<uint8_t>(k.y - base.y),
          static_cast<uint8_t>(k.z - base.z), static_cast<uint8_t>(std::clamp(q, 0.0, 255.0))};
}

VoxelKey LocalGrid::rememberedKey(const RememberedCell& c, const VoxelKey& block) const {
  return {block.x * kMemoryBlockSide + c.x, block.y * kMemoryBlockSide + c.y,
          block.z * kMemoryBlockSide + c.z};
}

float LocalGrid::rememberedLogodds(const RememberedCell& c) const {
  return static_cast<float>(
      std::min(cfg_.logodds_max, cfg_.logodds_min + c.logodds_q * rememberedLogoddsStep()));
}

void LocalGrid::restoreRemembered() {
  const VoxelKey lo = memoryBlock(min_key_), hi = memoryBlock(maxKey());
  for (int32_t bx = lo.x; bx <= hi.x; ++bx)
    for (int32_t by = lo.y; by <= hi.y; ++by)
      for (int32_t bz = lo.z; bz <= hi.z; ++bz) {
        const VoxelKey block{bx, by, bz};
        const auto it = memory_.find(block);
        if (it == memory_.end()) continue;
        std::vector<RememberedCell>& cells = it->second;
        size_t kept = 0;
        for (const RememberedCell& c : cells) {
          const VoxelKey key = rememberedKey(c, block);
          if (!inWindow(key)) {
            cells[kept++] = c;
            continue;
          }
          const size_t i = index(key);
          const bool was_occupied = cells_[i].occupied;
          cells_[i].logodds = rememberedLogodds(c);
          cells_[i].observed = 1;
          cells_[i].occupied = 1;
          setSettledFree(i, false);
          if (!was_occupied) stampInflation(key, +1);
        }
        remembered_ -= cells.size() - kept;
        cells.resize(kept);
        if (cells.empty()) memory_.erase(it);
      }
}

size_t LocalGrid::memoryBytes() const {
  size_t bytes = cells_.capacity() * sizeof(Cell) + settled_free_.capacity() * sizeof(uint64_t) +
                 hashContainerBytes(memory_);
  for (const auto& [block, cells] : memory_) bytes += cells.capacity() * sizeof(RememberedCell);
  return bytes;
}

void LocalGrid::cropMemory() {
  const Eigen::Vector3d c = 0.5 * (windowMin() + windowMax());
  const double block_m = cfg_.resolution_m * kMemoryBlockSide;
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

void LocalGrid::stampInflation(const VoxelKey& k, int sign, const EnteringSlots* only) {
  // Per-axis slots of the ball's reach once, then vertical runs: the inner loop walks z, the
  // ring buffer's contiguous axis. Called for every cell that turns occupied or free, for every
  // occupied cell that leaves or comes back with the window, and (`only`) for the occupied cells
  // that stay near the slots the window's move brought in, onto those slots alone.
  const int reach = kernel_reach_;
  const auto fill = [reach](std::vector<int>& slots, int key, int min_k, int phase, int n) {
    for (int o = -reach; o <= reach; ++o) {
      const int kk = key + o;
      slots[o + reach] = (kk < min_k || kk >= min_k + n) ? -1 : axisSlot(kk, min_k, phase, n);
    }
  };
  fill(stamp_slots_x_, k.x, min_key_.x, phase_.x, nx_);
  fill(stamp_slots_y_, k.y, min_key_.y, phase_.y, ny_);
  fill(stamp_slots_z_, k.z, min_key_.z, phase_.z, nz_);
  const bool narrow = has_narrow_;
  const int* sz = stamp_slots_z_.data() + reach;
  for (const KernelColumn& col : kernel_) {
    const int sx = stamp_slots_x_[col.dx + reach], sy = stamp_slots_y_[col.dy + reach];
    if (sx < 0 || sy < 0) continue;
    const size_t base = (static_cast<size_t>(sx) * ny_ + sy) * nz_;
    Cell* column = cells_.data() + base;
    const bool whole_column = !only || only->x[sx] || only->y[sy];
    for (int dz = -col.half_height; dz <= col.half_height; ++dz) {
      const int z = sz[dz];
      if (z < 0 || (!whole_column && !only->z[z])) continue;
      Cell& c = column[z];
      const bool in_narrow = narrow && std::abs(dz) <= col.narrow_half_height;
      if (sign > 0) {
        ++c.inflation;
        if (in_narrow) ++c.narrow_inflation;
      } else {
        if (c.inflation > 0) --c.inflation;
        if (in_narrow && c.narrow_inflation > 0) --c.narrow_inflation;
      }
    }
  }
}

void LocalGrid::updateCell(size_t idx, const VoxelKey& k, float delta) {
  Cell& c = cells_[idx];
  const bool was_occ = c.observed && c.logodds > cfg_.logodds_occupied;
  c.observed = 1;
  c.logodds = std::clamp(c.logodds + delta, static_cast<float>(cfg_.logodds_min),
                         static_cast<float>(cfg_.logodds_max));
  const bool is_occ = c.logodds > cfg_.logodds_occupied;
  c.occupied = is_occ;
  setSettledFree(idx, isSettledFree(c));
  if (is_occ != was_occ) stampInflation(k, is_occ ? +1 : -1);
}

void LocalGrid::insertScan(const Eigen::Vector3d& origin,
                           const std::vector<Eigen::Vector3d>& points) {
  if (++scan_id_ == 0) {  // wrapped: reset stamps so that old ones cannot collide
    for (Cell& c : cells_) c.scan_stamp = 0;
    scan_id_ = 1;
  }
  const double res = cfg_.resolution_m;
  // What a hit makes of a cell never seen; kept for hits outside the window only if occupied.
  const float hit_on_unknown = std::min(static_cast<float>(cfg_.logodds_max), hitDelta(0.f));
  const bool remember_outside =
      cfg_.memory_radius_m > 0.0 && hit_on_unknown > static_cast<float>(cfg_.logodds_occupied);
  // Hits first, so that a cell hit in this scan is not cleared by a grazing ray of the same scan.
  for (const auto& p : points) {
    if (!p.allFinite() || (p - origin).norm() > cfg_.max_ray_length_m) continue;
    const VoxelKey k = key(p);
    if (!inWindow(k)) {
      if (remember_outside) rememberHitAboveOrBelow(k, hit_on_unknown);
      continue;
    }
    const size_t idx = index(k);
    if (cells_[idx].scan_stamp == scan_id_) continue;
    cells_[idx].scan_stamp = scan_id_;
    updateCell(idx, k, hitDelta(cells_[idx].logodds));
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
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(res);
  const Eigen::Vector3d window_lo = windowMin() - margin, window_hi = windowMax() + margin;
  for (size_t r = 0; r < ray_bins_.size(); ++r) {
    if (r > 0 && ray_bins_[r].first == ray_bins_[r - 1].first) continue;
    const Eigen::Vector3d& p = points[ray_bins_[r].second];
    Eigen::Vector3d end = p;
    const double len = (p - origin).norm();
    if (len > cfg_.max_ray_length_m) end = origin + (p - origin) * (cfg_.max_ray_length_m / len);
    const VoxelKey end_key = key(end);
    // Only the part of the ray inside the window changes cells: long rays used to walk on
    // through tens of metres of cells outside it. A cell of margin keeps the boundary cells.
    const auto [t0, t1] = clipSegment(origin, end, window_lo, window_hi);
    if (t0 > t1) continue;
    const Eigen::Vector3d from = t0 > 0.0 ? Eigen::Vector3d(origin + t0 * (end - origin)) : origin;
    if (t1 < 1.0) end = origin + t1 * (end - origin);
    traverseCells(from, end, res, [&](const VoxelKey& k) {
      if (k == end_key) return false;
      if (!inWindow(k)) return true;  // the origin may be outside; keep walking inwards
      const size_t idx = index(k);
      // Unchanged by a miss: its stamp need not be read or set either, for a later ray of this
      // scan finds the bit as well (hits came first and clear it).
      if (settledFree(idx)) return true;
      if (cells_[idx].scan_stamp == scan_id_) return true;
      cells_[idx].scan_stamp = scan_id_;
      updateCell(idx, k,
                 static_cast<float>(cells_[idx].occupied ? cfg_.logodds_miss_occupied
                                                         : cfg_.logodds_miss));
      return true;
    });
  }
}

void LocalGrid::setOccupied(const Eigen::Vector3d& p) {
  const VoxelKey k = key(p);
  if (!inWindow(k)) return;
  const size_t idx = index(k);
  updateCell(idx, k, static_cast<float>(cfg_.logodds_max - cells_[idx].logodds));
}

void LocalGrid::setFree(const Eigen::Vector3d& p) {
  const VoxelKey k = key(p);
  if (!inWindow(k)) return;
  const size_t idx = index(k);
  updateCell(idx, k, static_cast<float>(cfg_.logodds_min - cells_[idx].logodds));
}

void LocalGrid::setAllFree() {
  for (Cell& c : cells_) {
    c.logodds = static_cast<float>(cfg_.logodds_min);
    c.observed = 1;
    c.occupied = 0;
    c.inflation = c.narrow_inflation = 0;
  }
  std::fill(settled_free_.begin(), settled_free_.end(), ~uint64_t{0});
}

CellState LocalGrid::state(const VoxelKey& k) const {
  if (!inWindow(k)) return CellState::kOutside;
  const Cell& c = cells_[index(k)];
  if (!c.observed) return CellState::kUnknown;
  return c.logodds > cfg_.logodds_occupied ? CellState::kOccupied : CellState::kFree;
}

bool LocalGrid::isInflated(const VoxelKey& k) const {
  return inWindow(k) && cells_[index(k)].inflation > 0;
}

bool LocalGrid::isBlocked(const VoxelKey& k, bool unknown_is_free,
                          double narrow_clearance_m) const {
  if (!inWindow(k)) return true;
  const Cell& c = cells_[index(k)];
  if (c.inflation > 0) {
    if (narrow_clearance_m <= 0.0 || narrow_clearance_m >= cfg_.inflation_radius_m || c.occupied)
      return true;
    if (has_narrow_ && std::abs(narrow_clearance_m - cfg_.narrow_radius_m) < 1e-9) {
      if (c.narrow_inflation > 0) return true;
    } else if (nearestOccupiedDistance(center(k), narrow_clearance_m)) {
      return true;
    }
  }
  return !unknown_is_free && !c.observed;
}

bool LocalGrid::isInterior(const VoxelKey& k) const {
  static const int kOff[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                 {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  for (const auto& o : kOff) {
    const VoxelKey n{k.x + o[0], k.y + o[1], k.z + o[2]};
    if (!inWindow(n) || !cells_[index(n)].occupied) return false;
  }
  return true;
}

std::pair<VoxelKey, VoxelKey> LocalGrid::keysInBox(const Eigen::Vector3d& lo,
                                                   const Eigen::Vector3d& hi) const {
  const double res = cfg_.resolution_m;
  const VoxelKey wmax = maxKey();
  return {{std::max(min_key_.x, static_cast<int>(std::ceil(lo.x() / res - 0.5))),
           std::max(min_key_.y, static_cast<int>(std::ceil(lo.y() / res - 0.5))),
           std::max(min_key_.z, static_cast<int>(std::ceil(lo.z() / res - 0.5)))},
          {std::min(wmax.x, static_cast<int>(std::floor(hi.x() / res - 0.5))),
           std::min(wmax.y, static_cast<int>(std::floor(hi.y() / res - 0.5))),
           std::min(wmax.z, static_cast<int>(std::floor(hi.z() / res - 0.5)))}};
}

void LocalGrid::occupiedCentersInBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                     std::vector<Eigen::Vector3d>& out, bool surface_only) const {
  const auto [k0, k1] = keysInBox(lo, hi);
  if (k1.z < k0.z) return;
  const int iz0 = posMod(k0.z, nz_);
  for (int x = k0.x; x <= k1.x; ++x)
    for (int y = k0.y; y <= k1.y; ++y) {
      const size_t base = (static_cast<size_t>(posMod(x, nx_)) * ny_ + posMod(y, ny_)) * nz_;
      int iz = iz0;
      for (int z = k0.z; z <= k1.z; ++z) {
        if (cells_[base + iz].occupied) {
          const VoxelKey k{x, y, z};
          if (!surface_only || !isInterior(k)) out.push_back(center(k));
        }
        if (++iz == nz_) iz = 0;
      }
    }
}

void LocalGrid::unobservedTopsBelow(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                    const std::function<double(double, double)>& top_z_m,
                                    std::vector<Eigen::Vector3d>& out) const {
  const auto [k0, k1] = keysInBox(lo, hi);
  for (int x = k0.x; x <= k1.x; ++x)
    for (int y = k0.y; y <= k1.y; ++y) {
      const Eigen::Vector3d column = center(VoxelKey{x, y, 0});
      const double top = top_z_m(column.x(), column.y());
      if (!std::isfinite(top)) continue;
      // Strictly below top: the centre (z + 0.5) res < top.
      const int zt = std::min(k1.z, static_cast<int>(std::ceil(top / cfg_.resolution_m - 0.5)) - 1);
      for (int z = zt; z >= k0.z; --z) {
        const VoxelKey k{x, y, z};
        if (!cells_[index(k)].observed) {
          out.push_back(center(k));
          break;
        }
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
        if (!inWindow(k) || !cells_[index(k)].occupied) continue;
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
  for (const Cell& c : cells_) n += c.occupied;
  return n;
}

}  // namespace efs::traj
