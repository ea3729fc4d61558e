// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/viewpoint_sampler.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "efs_common/config_check.h"

namespace efs::planner {
namespace {
constexpr double kPi = 3.14159265358979323846;
}

void LidarFovConfig::validate() const {
  requireInRange("lidar.min_elevation_rad", min_elevation_rad, -kPi / 2, kPi / 2);
  requireInRange("lidar.max_elevation_rad", max_elevation_rad, min_elevation_rad, kPi / 2);
  requireInRange("lidar.mount_pitch_rad", mount_pitch_rad, -kPi / 2, kPi / 2);
  requirePositive("lidar.max_range_m", max_range_m);
}

LidarFov::LidarFov(LidarFovConfig config) : config_(config) {
  config_.validate();
  cos_p_ = std::cos(config_.mount_pitch_rad);
  sin_p_ = std::sin(config_.mount_pitch_rad);
}

double LidarFov::sensorElevation(const Eigen::Vector3d& d, double yaw_rad) const {
  // Into the body frame (undo yaw), then into the sensor frame (undo the pitch about body y):
  // d_s = R_y(pitch)^T * R_z(yaw)^T * d.
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  const double bx = c * d.x() + s * d.y();
  const double by = -s * d.x() + c * d.y();
  const double bz = d.z();
  const double sx = cos_p_ * bx - sin_p_ * bz;
  const double sz = sin_p_ * bx + cos_p_ * bz;
  return std::atan2(sz, std::hypot(sx, by));
}

bool LidarFov::inFov(const Eigen::Vector3d& d, double yaw_rad) const {
  const double e = sensorElevation(d, yaw_rad);
  return e >= config_.min_elevation_rad && e <= config_.max_elevation_rad;
}

bool LidarFov::sees(const Eigen::Vector3d& sensor, double yaw_rad,
                    const Eigen::Vector3d& target) const {
  const Eigen::Vector3d d = target - sensor;
  const double r = d.norm();
  return r > 0.0 && r <= config_.max_range_m && inFov(d, yaw_rad);
}

void ViewpointConfig::validate() const {
  requireThat(!ring_radii_m.empty(), "viewpoint.ring_radii_m", "must not be empty");
  for (double r : ring_radii_m) requirePositive("viewpoint.ring_radii_m", r);
  requireThat(!height_offsets_m.empty(), "viewpoint.height_offsets_m", "must not be empty");
  for (double h : height_offsets_m) requireInRange("viewpoint.height_offsets_m", h, -100.0, 100.0);
  requireInRange("viewpoint.num_azimuths", num_azimuths, 1, 360);
  requireInRange("viewpoint.num_yaws", num_yaws, 1, 360);
  requireInRange("viewpoint.clearance_m", clearance_m, 0.0, 10.0);
  requirePositive("viewpoint.useful_range_m", useful_range_m);
  requireInRange("viewpoint.max_score_cells", max_score_cells, 1, 100000);
  requireInRange("viewpoint.min_visible_cells", min_visible_cells, 1, 100000);
  requireInRange("viewpoint.max_viewpoints_per_cluster", max_viewpoints_per_cluster, 1, 100);
  requireInRange("viewpoint.min_viewpoint_separation_m", min_viewpoint_separation_m, 0.0, 100.0);
  requireInRange("viewpoint.reuse_distance_m", reuse_distance_m, 0.0, 10.0);
}

ViewpointSampler::ViewpointSampler(ViewpointConfig config, LidarFovConfig fov)
    : config_(std::move(config)), fov_(fov) {
  config_.validate();
}

int ViewpointSampler::scoreAt(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& cells,
                              const OccupancyMap& occ, double* best_yaw_rad) const {
  const double range = std::min(config_.useful_range_m, fov_.config().max_range_m);
  const double pitch = std::abs(fov_.config().mount_pitch_rad);
  const double res = occ.resolution();
  std::vector<int> count(config_.num_yaws, 0);
  for (const Eigen::Vector3d& q : cells) {
    const Eigen::Vector3d d = q - p;
    const double r = d.norm();
    if (r > range || r < 1e-6) continue;
    // Yaw moves the sensor elevation of a direction by at most the mount pitch.
    const double el_body = std::atan2(d.z(), std::hypot(d.x(), d.y()));
    if (el_body < fov_.config().min_elevation_rad - pitch ||
        el_body > fov_.config().max_elevation_rad + pitch)
      continue;
    // Aim at the point of the target cell nearest to the sensor (its box shrunk by 1 %) and
    // ignore the target's 26 neighbours: the ray then stays clear of the surface layer that
    // the neighbours form, which would otherwise block every grazing view of a floor or wall
    // although the cell is in sight.
    const Eigen::Vector3d lo = q.array() - 0.49 * res, hi = q.array() + 0.49 * res;
    const Eigen::Vector3d aim = p.cwiseMax(lo).cwiseMin(hi);
    if (!occ.lineOfSight(p, aim, config_.unknown_blocks_view, 1)) continue;
    for (int y = 0; y < config_.num_yaws; ++y) {
      if (fov_.inFov(d, 2.0 * kPi * y / config_.num_yaws - kPi)) ++count[y];
    }
  }
  int best = 0, best_y = 0;
  for (int y = 0; y < config_.num_yaws; ++y) {
    if (count[y] > best) {
      best = count[y];
      best_y = y;
    }
  }
  if (best_yaw_rad) *best_yaw_rad = 2.0 * kPi * best_y / config_.num_yaws - kPi;
  return best;
}

std::vector<Viewpoint> ViewpointSampler::sample(const FrontierCluster& cluster, double res,
                                                const OccupancyMap& occ) const {
  std::vector<Eigen::Vector3d> cells;
  const size_t n = cluster.cells.size();
  const size_t m = std::min<size_t>(n, static_cast<size_t>(config_.max_score_cells));
  cells.reserve(m);
  for (size_t i = 0; i < m; ++i) cells.push_back(voxelCenter(cluster.cells[i * n / m], res));
  const double scale = static_cast<double>(n) / static_cast<double>(std::max<size_t>(m, 1));
  const double range = std::min(config_.useful_range_m, fov_.config().max_range_m);

  // Candidates with their upper bound (cells within range), best bound first; the costly
  // line-of-sight scoring stops once no remaining bound can beat the kept viewpoints.
  struct Candidate {
    Eigen::Vector3d p;
    int bound;
    int order;
  };
  std::vector<Candidate> cand;
  for (double radius : config_.ring_radii_m) {
    for (double dz : config_.height_offsets_m) {
      for (int a = 0; a < config_.num_azimuths; ++a) {
        const double az = 2.0 * kPi * a / config_.num_azimuths;
        const Eigen::Vector3d p = cluster.centroid_world_m +
                                  Eigen::Vector3d(radius * std::cos(az), radius * std::sin(az), dz);
        int in_range = 0;
        for (const Eigen::Vector3d& q : cells) in_range += (q - p).norm() <= range;
        if (in_range < config_.min_visible_cells) continue;
        cand.push_back({p, in_range, static_cast<int>(cand.size())});
      }
    }
  }
  std::stable_sort(cand.begin(), cand.end(),
                   [](const Candidate& a, const Candidate& b) { return a.bound > b.bound; });
  const size_t keep = static_cast<size_t>(config_.max_viewpoints_per_cluster);
  std::vector<std::pair<int, Viewpoint>> scored;  // (generation order, viewpoint)
  auto better = [&](const std::pair<int, Viewpoint>& a, const std::pair<int, Viewpoint>& b) {
    if (a.second.visible_cells != b.second.visible_cells)
      return a.second.visible_cells > b.second.visible_cells;
    const double da = (a.second.position_world_m - cluster.centroid_world_m).squaredNorm();
    const double db = (b.second.position_world_m - cluster.centroid_world_m).squaredNorm();
    if (std::abs(da - db) > 1e-9) return da < db;  // ties: closer to the cluster
    return a.first < b.first;
  };
  std::vector<std::pair<int, Viewpoint>> kept;
  auto rebuildKept = [&] {
    std::sort(scored.begin(), scored.end(), better);
    kept.clear();
    for (const auto& v : scored) {
      if (kept.size() >= keep) break;
      bool far = true;
      for (const auto& k : kept)
        far = far && (k.second.position_world_m - v.second.position_world_m).norm() >=
                         config_.min_viewpoint_separation_m;
      if (far) kept.push_back(v);
    }
  };
  for (const Candidate& c : cand) {
    // A full kept list whose worst member sees at least what this candidate could: done.
    // (Ties therefore go to the candidate with the larger bound, then the generation order.)
    if (kept.size() >= keep && std::lround(c.bound * scale) <= kept.back().second.visible_cells)
      break;
    if (!viewpointSafe(occ, c.p)) continue;
    double yaw = 0.0;
    const int seen = scoreAt(c.p, cells, occ, &yaw);
    if (seen < config_.min_visible_cells) continue;
    Viewpoint v;
    v.cluster_id = cluster.id;
    v.position_world_m = c.p;
    v.yaw_rad = yaw;
    v.visible_cells = static_cast<int>(std::lround(seen * scale));
    scored.emplace_back(c.order, v);
    rebuildKept();
  }
  std::vector<Viewpoint> out;
  for (const auto& k : kept) out.push_back(k.second);
  return out;
}

ViewpointManager::ViewpointManager(ViewpointSampler sampler) : sampler_(std::move(sampler)) {}

void ViewpointManager::retire(std::map<int, std::vector<Viewpoint>>::iterator it) {
  retired_.insert(retired_.end(), it->second.begin(), it->second.end());
  by_cluster_.erase(it);
}

void ViewpointManager::assignId(Viewpoint& v, const OccupancyMap& occ) {
  const double reuse = sampler_.config().reuse_distance_m;
  auto best = retired_.end();
  double best_d = reuse;
  for (auto it = retired_.begin(); it != retired_.end(); ++it) {
    const double d = (it->position_world_m - v.position_world_m).norm();
    if (d <= best_d) best_d = d, best = it;
  }
  if (best != retired_.end() && sampler_.viewpointSafe(occ, best->position_world_m)) {
    v.id = best->id;
    v.position_world_m = best->position_world_m;
    retired_.erase(best);
    return;
  }
  v.id = next_id_++;
}

void ViewpointManager::resample(const FrontierCluster& c, const OccupancyMap& occ, double res) {
  if (auto it = by_cluster_.find(c.id); it != by_cluster_.end()) retire(it);
  sampled_.insert(c.id);
  if (c.too_small) return;
  std::vector<Viewpoint> vps = sampler_.sample(c, res, occ);
  if (vps.empty()) return;
  for (Viewpoint& v : vps) assignId(v, occ);
  by_cluster_[c.id] = std::move(vps);
}

ViewpointUpdateStats ViewpointManager::update(const FrontierClusterer& clusterer,
                                              const OccupancyMap& occ, double res) {
  ViewpointUpdateStats st;
  retired_.clear();
  const auto& clusters = clusterer.clusters();
  // Drop what belongs to clusters that are gone (changed clusters come back under a new id, and
  // their viewpoints, where they land again, under the old ids).
  for (auto it = sampled_.begin(); it != sampled_.end();) {
    if (!clusters.count(*it)) {
      if (auto vit = by_cluster_.find(*it); vit != by_cluster_.end()) retire(vit);
      it = sampled_.erase(it);
    } else {
      ++it;
    }
  }
  const bool occ_changed = occ.revision() != seen_occ_revision_;
  seen_occ_revision_ = occ.revision();
  for (const auto& [id, c] : clusters) {
    if (!sampled_.count(id)) {
      resample(c, occ, res);
      ++st.clusters_sampled;
      continue;
    }
    if (!occ_changed) continue;
    auto it = by_cluster_.find(id);
    if (it == by_cluster_.end()) continue;
    bool ok = true;
    for (const Viewpoint& v : it->second)
      ok = ok && sampler_.viewpointSafe(occ, v.position_world_m);
    if (!ok) {
      resample(c, occ, res);
      ++st.clusters_rechecked;
    }
  }
  retired_.clear();
  for (const auto& [id, c] : clusters) {
    (void)c;
    if (!by_cluster_.count(id)) ++st.clusters_without_viewpoint;
  }
  for (const auto& [id, v] : by_cluster_) st.viewpoints_total += v.size();
  return st;
}

std::vector<Viewpoint> ViewpointManager::all() const {
  std::vector<Viewpoint> out;
  for (const auto& [id, v] : by_cluster_) out.insert(out.end(), v.begin(), v.end());
  return out;
}

}  // namespace efs::planner
