// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Viewpoints around frontier clusters, scored with the LiDAR's real field of view.
//  - LidarFov: Livox Mid-360 (360 deg azimuth, -7 to +52 deg elevation in the sensor frame)
//    mounted on a level vehicle with a pitch about the body y axis (REP 103: a positive pitch
//    turns the sensor's x axis down, so it sees lower in front and higher behind).
//  - ViewpointSampler: candidate positions on rings around the cluster centroid (several radii
//    and height offsets), kept when the ball of `clearance_m` around them is known free; each
//    is scored with the number of cluster cells it would see (in the FoV for some yaw, within
//    `useful_range_m`, line of sight not blocked in the occupancy) at its best yaw.
//    `useful_range_m` defaults to the observation map's well-observed distance: a cell seen
//    from farther would stay poorly observed, so it does not count.
//  - ViewpointManager: keeps the best viewpoints of every cluster; re-samples a cluster when it
//    changed (new id) or when one of its viewpoints is no longer safe; drops clusters with
//    nothing left to see.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <map>
#include <set>
#include <vector>

#include "prior_guided_planner/frontier_clusters.h"
#include "prior_guided_planner/occupancy_map.h"

namespace efs::planner {

struct LidarFovConfig {
  double min_elevation_rad = -7.0 * 3.14159265358979323846 / 180.0;
  double max_elevation_rad = 52.0 * 3.14159265358979323846 / 180.0;
  double mount_pitch_rad = 15.0 * 3.14159265358979323846 / 180.0;
  double max_range_m = 40.0;
  void validate() const;
};

class LidarFov {
 public:
  explicit LidarFov(LidarFovConfig config = {});
  const LidarFovConfig& config() const { return config_; }
  /// Elevation [rad] of a world-frame direction in the sensor frame of a level vehicle with yaw.
  double sensorElevation(const Eigen::Vector3d& dir_world, double yaw_rad) const;
  /// Direction inside the elevation band (azimuth is unlimited). Range is not checked here.
  bool inFov(const Eigen::Vector3d& dir_world, double yaw_rad) const;
  /// inFov and 0 < |target - sensor| <= max_range_m.
  bool sees(const Eigen::Vector3d& sensor_world_m, double yaw_rad,
            const Eigen::Vector3d& target_world_m) const;

 private:
  LidarFovConfig config_;
  double cos_p_, sin_p_;
};

struct ViewpointConfig {
  std::vector<double> ring_radii_m{1.5, 2.5, 3.5};
  std::vector<double> height_offsets_m{-1.0, 0.0, 1.0};
  int num_azimuths = 12;
  int num_yaws = 12;
  /// Free ball required around a viewpoint (vehicle radius plus margin).
  double clearance_m = 0.5;
  /// Cells farther than this do not count (defaults to the well-observed distance).
  double useful_range_m = 5.0;
  /// Large clusters are scored on an evenly strided subset of this many cells.
  int max_score_cells = 60;
  /// A viewpoint must see at least this many (sampled) cells; otherwise the cluster has none.
  int min_visible_cells = 2;
  int max_viewpoints_per_cluster = 2;
  /// Extra viewpoints of one cluster must be at least this far from the kept ones.
  double min_viewpoint_separation_m = 1.0;
  bool unknown_blocks_view = false;
  /// The whole clearance ball must be known free (else: no occupied cell in it). A viewpoint
  /// beside a floor not seen yet was taken for safe (seen: viewpoints 0.35 m above an office
  /// floor, the vehicle hitting it on the way down).
  bool require_known_free = true;
  /// A viewpoint sampled again (its cluster changed by a cell, or was rebuilt) that lands within
  /// this distance of one it replaces keeps that one's id and place, if still safe. In a mapped
  /// garage the clusters were rebuilt every scan under new ids: every planning cycle searched
  /// the whole tour matrix again and sent the local planner a goal a few centimetres off.
  /// 0: every sample is new.
  double reuse_distance_m = 0.3;
  void validate() const;
};

struct Viewpoint {
  int id = -1;
  int cluster_id = -1;
  Eigen::Vector3d position_world_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
  /// Cluster cells seen (on the scored subset, scaled to the whole cluster).
  int visible_cells = 0;
};

class ViewpointSampler {
 public:
  ViewpointSampler(ViewpointConfig config = {}, LidarFovConfig fov = {});
  const ViewpointConfig& config() const { return config_; }
  const LidarFov& fov() const { return fov_; }

  /// Cells of `cells` visible from `p` per yaw sample; returns the best count and its yaw.
  int scoreAt(const Eigen::Vector3d& p_world_m, const std::vector<Eigen::Vector3d>& cells_world_m,
              const OccupancyMap& occ, double* best_yaw_rad) const;
  /// Whether a viewpoint at p is safe to hover at (clearance_m, require_known_free).
  bool viewpointSafe(const OccupancyMap& occ, const Eigen::Vector3d& p_world_m) const {
    return config_.require_known_free ? occ.isKnownFree(p_world_m, config_.clearance_m)
                                      : occ.isSafe(p_world_m, config_.clearance_m, true);
  }
  /// Best viewpoints of a cluster, best first (ids unset); empty when nothing can be seen.
  std::vector<Viewpoint> sample(const FrontierCluster& cluster, double resolution_m,
                                const OccupancyMap& occ) const;

 private:
  ViewpointConfig config_;
  LidarFov fov_;
};

struct ViewpointUpdateStats {
  size_t clusters_sampled = 0;
  size_t clusters_rechecked = 0;
  size_t clusters_without_viewpoint = 0;
  size_t viewpoints_total = 0;
};

class ViewpointManager {
 public:
  explicit ViewpointManager(ViewpointSampler sampler = ViewpointSampler());

  /// Brings the viewpoints in line with the clusterer's last update and the occupancy.
  ViewpointUpdateStats update(const FrontierClusterer& clusters, const OccupancyMap& occ,
                              double resolution_m);
  /// Viewpoints by cluster id (clusters with nothing to see are absent).
  const std::map<int, std::vector<Viewpoint>>& byCluster() const { return by_cluster_; }
  /// All viewpoints, ordered by cluster id then rank.
  std::vector<Viewpoint> all() const;
  const ViewpointSampler& sampler() const { return sampler_; }

 private:
  void resample(const FrontierCluster& c, const OccupancyMap& occ, double res);
  /// Moves a cluster's viewpoints to the ones this update replaces.
  void retire(std::map<int, std::vector<Viewpoint>>::iterator it);
  /// An id for a new viewpoint: a replaced one's (taking over its place) or a fresh one.
  void assignId(Viewpoint& v, const OccupancyMap& occ);

  ViewpointSampler sampler_;
  std::vector<Viewpoint> retired_;  ///< replaced during the running update, ids not taken yet
  std::map<int, std::vector<Viewpoint>> by_cluster_;
  std::set<int> sampled_;  ///< clusters already sampled, with or without a viewpoint
  uint64_t seen_occ_revision_ = 0;
  int next_id_ = 0;
};

}  // namespace efs::planner
