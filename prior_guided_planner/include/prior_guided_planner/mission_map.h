// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// What a mission leaves behind for the user (the paper's problem statement: explore the space
// and produce a dense point-cloud map), all in the world frame:
//   cloud.pcd          the dense point cloud, one centroid per cloud_voxel_m voxel
//   occupancy.bt       the planner's occupancy map as an OctoMap (free and occupied cells)
//   trajectory.csv     the flown track (time, position, yaw), one sample per trajectory_spacing_m
//   registration.yaml  the sketch-to-world similarities known at the end, best first, and the
//                      last one the planner's guidance used
// The ROS planner node and the in-process mission both keep one and save it at the end.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "lio_bridge/local_map.h"
#include "prior_guided_planner/occupancy_map.h"
#include "prior_guided_planner/planner_types.h"

namespace efs::planner {

struct MissionMapConfig {
  double cloud_voxel_m = 0.1;         ///< resolution of the dense cloud [m]
  double max_range_m = 40.0;          ///< scan points farther from the sensor are not kept [m]
  double trajectory_spacing_m = 0.2;  ///< a track sample every this much flight [m]
  void validate() const;
};

struct TrackSample {
  double time_s = 0.0;
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
};

/// The registration state written beside the map.
struct MapRegistration {
  std::vector<Hypothesis> hypotheses;       ///< best first; empty when nothing was registered
  std::optional<int> active_hypothesis_id;  ///< the last one the guidance used, if any
  std::string world_frame = "world";
  std::string sketch_frame = "sketch";
};

/// Paths and counts of what save() wrote.
struct SavedMissionMap {
  std::string directory, cloud_pcd, occupancy_bt, trajectory_csv, registration_yaml;
  size_t cloud_points = 0, occupied_cells = 0, free_cells = 0, track_samples = 0;
};

class MissionMap {
 public:
  /// Throws efs::ConfigError naming the key for a bad configuration.
  explicit MissionMap(const MissionMapConfig& config = {});

  /// A registered scan (world frame) taken at `sensor_world_m`; non-finite points and points
  /// beyond max_range_m are skipped. Returns the number of points kept.
  size_t insertScan(const Eigen::Vector3d& sensor_world_m,
                    const std::vector<Eigen::Vector3f>& points_world_m);
  /// The vehicle at `time_s`; kept when it moved trajectory_spacing_m since the last sample
  /// (the first pose is always kept). Non-finite poses are ignored (false).
  bool addPose(double time_s, const Eigen::Vector3d& p_world_m, double yaw_rad);

  size_t cloudSize() const { return cloud_.size(); }
  std::vector<Eigen::Vector3f> cloud() const { return cloud_.points(); }
  const std::vector<TrackSample>& track() const { return track_; }

  /// Writes the four files into `directory` (created if missing). Throws std::runtime_error
  /// naming the file when one cannot be written; files already written stay.
  SavedMissionMap save(const std::string& directory, const OccupancyMap& occupancy,
                       const MapRegistration& registration) const;

 private:
  MissionMapConfig config_;
  lio::LocalMap cloud_;
  std::vector<TrackSample> track_;
};

/// The occupancy map as an OctoMap file (.bt: binary free/occupied, the format octomap_server,
/// octovis and rviz's OctoMap plugin load). Returns the counts of occupied and free cells.
std::pair<size_t, size_t> writeOccupancyOctomap(const OccupancyMap& occupancy,
                                                const std::string& path);

}  // namespace efs::planner
