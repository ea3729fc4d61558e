// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// FAST-LIO2's `camera_init` frame is the IMU frame at start-up: if the vehicle stood tilted, that
// frame is tilted and a 2D sketch registered in it would be wrong. This estimates the rotation
// R_world_camerainit that makes z point against gravity, from accelerometer samples taken while
// the vehicle stands still (yaw is left unchanged).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

namespace efs::lio {

struct GravityAlignmentConfig {
  int samples_needed = 200;            ///< accelerometer samples averaged (1 s at 200 Hz)
  double max_accel_spread_mps2 = 0.5;  ///< samples farther than this from the mean: not still
  void validate() const;
};

class GravityAligner {
 public:
  explicit GravityAligner(const GravityAlignmentConfig& config = {});

  /// Adds a specific-force sample in the camera_init frame [m/s^2] (an IMU at rest reads +g up).
  void add(const Eigen::Vector3d& accel);

  /// The aligning rotation once enough still samples arrived; empty before, or if the vehicle
  /// moved (the spread check failed, in which case call reset() and try again).
  std::optional<Eigen::Quaterniond> rotation() const;
  bool moved() const { return moved_; }
  void reset();

  /// The minimal rotation taking unit vector `up_measured` to +z.
  static Eigen::Quaterniond alignToZ(const Eigen::Vector3d& up_measured);

 private:
  GravityAlignmentConfig config_;
  Eigen::Vector3d sum_ = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> samples_;
  bool moved_ = false;
};

}  // namespace efs::lio
