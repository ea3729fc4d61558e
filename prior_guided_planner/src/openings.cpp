// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/openings.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "efs_common/config_check.h"
#include "prior_guided_planner/observation_map.h"

namespace efs::planner {

void OpeningConfig::validate() const {
  requireInRange("openings.min_cells", min_cells, 1, 1000000);
  requireInRange("openings.viewpoint_clearance_m", viewpoint_clearance_m, 0.0, 10.0);
  requireInRange("openings.narrow_viewpoint_clearance_m", narrow_viewpoint_clearance_m, 0.0,
                 viewpoint_clearance_m);
  requireInRange("openings.max_backoff_m", max_backoff_m, 0.0, 100.0);
  requireInRange("openings.max_walk_cells", max_walk_cells, 0, 10000000);
  requireInRange("openings.vouched_min_cells", vouched_min_cells, 0, min_cells);
  requireInRange("openings.vouched_radius_m", vouched_radius_m, 0.0, 1000.0);
  requireInRange("openings.vouched_unseen_radius_m", vouched_unseen_radius_m, 0.0, 100.0);
  requireInRange("openings.vouched_unseen_fraction", vouched_unseen_fraction, 0.0, 1.0);
  requireInRange("openings.search_radius_m", search_radius_m, 1.0, 100000.0);
}

namespace {

/// The viewpoint search starts from at most this many cluster cells (nearest the centroid).
constexpr size_t kMaxViewpointStarts = 32;

/// Where to look through an opening from: the first known-free place (a ball of
/// `clearance_m`) stepping back from the opening cells nearest its centre (`starts`)
/// away from the unknown side, up to max_backoff_m, a cell or two up where a floor was not
/// seen; failing that, the known-free place nearest the opening along the known free space (up
/// to max_walk_cells); failing that, on the way back to the robot from the cell nearest the
/// centre.
std::optional<Eigen::Vector3d> hoverPlace(const OccupancyMap& occ,
                                          const std::vector<Eigen::Vector3d>& starts,
                                          const Eigen::Vector2d& away, const Eigen::Vector3d& robot,
                                          const OpeningConfig& cfg, double clearance_m) {
  const double res = occ.resolution();
  const auto knownFree = [&](const Eigen::Vector3d& p) -> std::optional<Eigen::Vector3d> {
    for (const int dz : {0, 1, 2}) {
      const Eigen::Vector3d q = p + Eigen::Vector3d(0, 0, dz * res);
      if (occ.isKnownFree(q, clearance_m)) return q;
    }
    return std::nullopt;
  };
  const int back_steps = static_cast<int>(std::floor(cfg.max_backoff_m / res + 1e-9));
  const Eigen::Vector3d step(res * away.x(), res * away.y(), 0.0);
  for (int s = 0; s <= back_steps; ++s)
    for (const Eigen::Vector3d& c : starts)
      if (const auto p = knownFree(c + s * step)) return p;
  if (starts.empty()) return std::nullopt;
  if (cfg.max_walk_cells > 0) {
    // Breadth first over known-free cells from the opening's: an opening seen from afar (a
    // room seen through its door from the corridor) is known free only along the rays, which
    // the walk follows back until the space around them is known free too. Only cells whose
    // six face neighbours are free can hold the ball, so only those are tested.
    std::unordered_set<VoxelKey, VoxelKeyHash> seen;
    std::deque<VoxelKey> queue;
    for (const Eigen::Vector3d& c : starts)
      if (seen.insert(occ.key(c)).second) queue.push_back(occ.key(c));
    static const VoxelKey kFaces[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                       {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    int walked = 0;
    while (!queue.empty() && walked++ < cfg.max_walk_cells) {
      const VoxelKey k = queue.front();
      queue.pop_front();
      const bool faces_free =
          std::all_of(std::begin(kFaces), std::end(kFaces), [&](const VoxelKey& o) {
            return occ.isFree({k.x + o.x, k.y + o.y, k.z + o.z});
          });
      if (faces_free && occ.isKnownFree(occ.center(k), clearance_m)) return occ.center(k);
      for (const VoxelKey& o : neighbourOffsets26()) {
        const VoxelKey n{k.x + o.x, k.y + o.y, k.z + o.z};
        if (occ.isFree(n) && seen.insert(n).second) queue.push_back(n);
      }
    }
  }
  const Eigen::Vector3d to_robot = robot - starts.front();
  const int steps = static_cast<int>(std::ceil(to_robot.norm() / res));
  for (int s = 1; s <= steps; ++s)
    if (const auto p = knownFree(starts.front() + (static_cast<double>(s) / steps) * to_robot))
      return p;
  return std::nullopt;
}

}  // namespace

std::vector<Opening> findOpenings(const OccupancyMap& occ, const Eigen::Vector3d& robot,
                                  const std::optional<Eigen::AlignedBox3d>& bounds,
                                  const OpeningConfig& cfg) {
  cfg.validate();
  if (!robot.allFinite()) return {};
  return findOpenings(occ, openingCellsOf(occ, bounds), robot, cfg);
}

std::vector<Opening> findOpenings(const OccupancyMap& occ, const OpeningCells& cells,
                                  const Eigen::Vector3d& robot, const OpeningConfig& cfg,
                                  const std::vector<Eigen::Vector2d>& vouched) {
  cfg.validate();
  std::vector<Opening> out;
  if (!robot.allFinite()) return out;
  const double r2 = cfg.search_radius_m * cfg.search_radius_m;
  // 26-connected clusters of the cells in range, each with where its viewpoint search starts.
  struct Candidate {
    Opening opening;  ///< all but the viewpoint
    std::vector<Eigen::Vector3d> starts;
    Eigen::Vector2d away = Eigen::Vector2d::Zero();
  };
  std::vector<Candidate> candidates;
  std::unordered_set<VoxelKey, VoxelKeyHash> pending;
  for (const auto& [k, unused] : cells)
    if ((occ.center(k) - robot).head<2>().squaredNorm() <= r2) pending.insert(k);
  while (!pending.empty()) {
    const std::vector<VoxelKey> cluster = takeComponent26(*pending.begin(), pending);
    const int size = static_cast<int>(cluster.size());
    const bool may_be_vouched =
        cfg.vouched_min_cells > 0 && size >= cfg.vouched_min_cells && !vouched.empty();
    if (size < cfg.min_cells && !may_be_vouched) continue;
    // Integer key sums: the centroid and each cell's distance to it are exact, so the starts
    // do not depend on the order the cluster's cells come in (hash-set order).
    int64_t sum[3] = {0, 0, 0};
    Eigen::Vector2d dir = Eigen::Vector2d::Zero();
    VoxelKey smallest = cluster.front();
    for (const VoxelKey& k : cluster) {
      sum[0] += k.x;
      sum[1] += k.y;
      sum[2] += k.z;
      dir += cells.at(k);
      if (voxelKeyLess(k, smallest)) smallest = k;
    }
    const int64_t n = static_cast<int64_t>(cluster.size());
    if (size < cfg.min_cells) {
      // The sketch's place must lie within reach and in view across unknown space: a pocket in
      // a cave wall has rock between it and a guidepoint that a deformed drawing put into the
      // rock (unknown too, but behind the wall's occupied surface).
      const double nd = static_cast<double>(n);
      const Eigen::Vector3d centre =
          occ.resolution() *
          (Eigen::Vector3d(static_cast<double>(sum[0]) / nd, static_cast<double>(sum[1]) / nd,
                           static_cast<double>(sum[2]) / nd) +
           Eigen::Vector3d::Constant(0.5));
      const double r2 = cfg.vouched_radius_m * cfg.vouched_radius_m;
      if (std::none_of(vouched.begin(), vouched.end(), [&](const Eigen::Vector2d& v) {
            return (v - centre.head<2>()).squaredNorm() <= r2 &&
                   occ.lineOfSight(centre, Eigen::Vector3d(v.x(), v.y(), centre.z()), false);
          }))
        continue;
    }
    const auto offsetSquared = [&](const VoxelKey& k) {  // (n (k - centroid))^2 in cells^2
      const double dx = static_cast<double>(n * k.x - sum[0]);
      const double dy = static_cast<double>(n * k.y - sum[1]);
      const double dz = static_cast<double>(n * k.z - sum[2]);
      return dx * dx + dy * dy + dz * dz;
    };
    // Nearest the centroid first; equally near cells by key.
    std::vector<std::pair<double, VoxelKey>> by_distance;
    for (const VoxelKey& k : cluster) by_distance.push_back({offsetSquared(k), k});
    std::sort(by_distance.begin(), by_distance.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first < b.first : voxelKeyLess(a.second, b.second);
    });
    if (by_distance.size() > kMaxViewpointStarts) by_distance.resize(kMaxViewpointStarts);
    Candidate c;
    for (const auto& [unused, k] : by_distance) c.starts.push_back(occ.center(k));
    if (dir.squaredNorm() > 0.0) c.away = -dir.normalized();
    // Ids live far above the observation viewpoints' (which count up from 0).
    const size_t h = VoxelKeyHash()(smallest);
    c.opening.id = (1 << 30) + static_cast<int>(h % (size_t{1} << 29));
    c.opening.yaw_rad = dir.squaredNorm() > 0.0 ? std::atan2(dir.y(), dir.x()) : 0.0;
    c.opening.cells = static_cast<int>(cluster.size());
    candidates.push_back(std::move(c));
  }
  const auto place = [&](double clearance_m) {
    for (const Candidate& c : candidates) {
      const std::optional<Eigen::Vector3d> best =
          hoverPlace(occ, c.starts, c.away, robot, cfg, clearance_m);
      if (!best) continue;
      out.push_back(c.opening);
      out.back().viewpoint_world_m = *best;
    }
  };
  place(cfg.viewpoint_clearance_m);
  // Only when no opening has room for the full ball: where one has, the flight goes on through
  // it, and narrow places in the plan beside it made the small indoor flights slower.
  if (out.empty() && cfg.narrow_viewpoint_clearance_m > 0.0)
    place(cfg.narrow_viewpoint_clearance_m);
  std::sort(out.begin(), out.end(), [](const Opening& a, const Opening& b) {
    return a.cells != b.cells ? a.cells > b.cells : a.id < b.id;
  });
  return out;
}

std::vector<Opening> openingsToTour(const std::vector<Eigen::Vector3d>& surface_viewpoints_world_m,
                                    const Eigen::Vector3d& robot_world_m, double near_radius_m,
                                    int near_min_cells,
                                    const std::function<const std::vector<Opening>&()>& find) {
  const auto near = [&](const Eigen::Vector3d& p) {
    return (p - robot_world_m).head<2>().norm() <= near_radius_m;
  };
  const bool none_left = surface_viewpoints_world_m.empty();
  const bool none_near =
      near_radius_m > 0.0 &&
      std::none_of(surface_viewpoints_world_m.begin(), surface_viewpoints_world_m.end(), near);
  if (!none_left && !none_near) return {};
  std::vector<Opening> out;
  for (const Opening& o : find())
    if (none_left || (o.cells >= near_min_cells && near(o.viewpoint_world_m))) out.push_back(o);
  return out;
}

std::vector<Opening> OpeningTourMembership::select(
    const std::vector<Eigen::Vector3d>& surface_viewpoints_world_m,
    const Eigen::Vector3d& robot_world_m, double near_radius_m, int near_min_cells,
    const std::function<const std::vector<Opening>&()>& find) {
  if (joined_) {
    const std::vector<Opening>& all = find();
    joined_ = !all.empty();
    return all;
  }
  std::vector<Opening> out = openingsToTour(surface_viewpoints_world_m, robot_world_m,
                                            near_radius_m, near_min_cells, find);
  // The first plan of a flight, over the map of one scan, has no surface viewpoint yet: the
  // openings join there and, where some are always found (a large garage), stay in every tour.
  // Waiting for surface viewpoints to run out instead (tried at stop 39) made most quick-tier
  // flights slower (README, "Openings are toured from the first plan").
  joined_ = stay_once_joined_ && surface_viewpoints_world_m.empty() && !out.empty();
  return out;
}

void ReachedOpeningsConfig::validate() const {
  requireInRange("reached_opening_moved_m", moved_m, 0.0, 1e4);
  requireInRange("opening_max_visits", max_visits, 1, 1000);
}

ReachedOpenings::ReachedOpenings(ReachedOpeningsConfig config) : config_(config) {
  config_.validate();
}

void ReachedOpenings::markReached(int id, const Eigen::Vector3d& viewpoint_world_m) {
  Visit& v = visits_[id];
  v.viewpoint_world_m = viewpoint_world_m;
  ++v.count;
}

bool ReachedOpenings::visited(const Opening& opening) const {
  return visits_.count(opening.id) > 0;
}

bool ReachedOpenings::movedOn(const Opening& opening) const {
  const auto v = visits_.find(opening.id);
  return v != visits_.end() && v->second.count < config_.max_visits &&
         (opening.viewpoint_world_m - v->second.viewpoint_world_m).norm() > config_.moved_m;
}

std::vector<Eigen::Vector2d> unseenPlaces(KnownColumns& known,
                                          const std::vector<Eigen::Vector2d>& places_world_m,
                                          double unseen_radius_m, double min_unseen_fraction) {
  // Whole columns: a place at the flight height inside the rock above a lower passage is unknown
  // there, but that passage was seen. The small cave climbs (its precise flight from 9.7 to
  // 15.1 m); judged at the flight height, places of its drawing in columns seen above or below
  // vouched, and that flight toured 81 pockets, 22.7 -> 105.4 s.
  std::vector<Eigen::Vector2d> out;
  const OccupancyMap& occ = known.map();
  const double res = occ.resolution();
  const int reach = static_cast<int>(std::floor(std::max(0.0, unseen_radius_m) / res));
  for (const Eigen::Vector2d& w : places_world_m) {
    if (!w.allFinite()) continue;
    const VoxelKey centre = occ.key(Eigen::Vector3d(w.x(), w.y(), 0.0));
    if (known.seen(centre.x, centre.y)) continue;
    // Columns on the place's cell lattice, so that the fraction does not depend on where in its
    // cell the place lies.
    int cells = 0, unseen_cells = 0;
    for (int dx = -reach; dx <= reach; ++dx) {
      for (int dy = -reach; dy <= reach; ++dy) {
        if ((dx * dx + dy * dy) * res * res > unseen_radius_m * unseen_radius_m) continue;
        ++cells;
        unseen_cells += known.seen(centre.x + dx, centre.y + dy) ? 0 : 1;
      }
    }
    if (unseen_cells >= min_unseen_fraction * cells) out.push_back(w);
  }
  return out;
}

}  // namespace efs::planner
