// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The accumulated, voxel-downsampled map around the robot that registration and planning read:
// one point (the running centroid) per voxel, kept within a horizontal window around the robot
// so memory stays bounded on a 2 km flight.
#pragma once

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "efs_common/voxel_key.h"

namespace efs::lio {

struct LocalMapConfig {
  double voxel_size_m = 0.3;      ///< downsampling resolution [m]
  double window_radius_m = 60.0;  ///< voxels farther (horizontally) from the robot are dropped [m]
  double max_range_m = 40.0;      ///< scan points farther than this from the sensor are ignored [m]
  void validate() const;
};

class LocalMap {
 public:
  explicit LocalMap(const LocalMapConfig& config = {});

  /// Inserts a registered scan (world frame) taken at `sensor_world_m`; non-finite points and
  /// points beyond max_range are skipped. Returns the number of points used.
  size_t insert(const std::vector<Eigen::Vector3f>& points_world,
                const Eigen::Vector3d& sensor_world_m);

  /// Drops voxels outside the window around `robot_world_m`.
  void crop(const Eigen::Vector3d& robot_world_m);

  std::vector<Eigen::Vector3f> points() const;
  size_t size() const { return voxels_.size(); }
  void clear() { voxels_.clear(); }

 private:
  struct Cell {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    uint32_t count = 0;
  };
  LocalMapConfig config_;
  std::unordered_map<VoxelKey, Cell, VoxelKeyHash> voxels_;
};

/// Emits a registration frame every 1 / rate_hz seconds of (injected) time: the paper samples
/// frames at 0.2 Hz (Sec. V).
class FrameDecimator {
 public:
  explicit FrameDecimator(double rate_hz = 0.2);
  /// True if a frame is due at `now_s` (and marks it as taken).
  bool due(double now_s);

 private:
  double period_s_;
  bool first_ = true;
  double last_s_ = 0.0;
};

}  // namespace efs::lio
