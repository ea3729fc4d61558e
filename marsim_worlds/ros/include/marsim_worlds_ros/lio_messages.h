// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The simulator's outputs as the messages FAST-LIO2 publishes (`cloud_registered` in the LIO frame,
// `Odometry` without twist by default) plus the ground truth, produced once per new output. The
// node publishes them; record_flight writes them to a bag; both through this one class.
#pragma once

#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>

#include <optional>
#include <string>

#include "marsim_worlds/simulator.h"

namespace efs::sim {

struct LioMessageConfig {
  std::string lio_frame = "camera_init";  ///< FAST-LIO2's world frame
  std::string body_frame = "body";
  std::string truth_frame = "world_truth";
  bool publish_twist = false;  ///< FAST-LIO2's /Odometry carries no twist
};

/// nav_msgs/Odometry with the twist in the child frame (REP 103) when `with_twist`.
nav_msgs::Odometry toOdometryMsg(const ros::Time& stamp, const std::string& frame,
                                 const std::string& child, const Eigen::Vector3d& p,
                                 const Eigen::Quaterniond& q, const Eigen::Vector3d& v_world,
                                 const Eigen::Vector3d& omega_body, bool with_twist);

class LioMessages {
 public:
  explicit LioMessages(LioMessageConfig config = {}) : config_(std::move(config)) {}
  /// The estimated odometry, when the simulator has a new one since the last call.
  std::optional<nav_msgs::Odometry> newOdometry(const Simulator& sim);
  /// The ground-truth state at the simulator's current time (twist included).
  nav_msgs::Odometry groundTruth(const Simulator& sim) const;
  /// The body IMU (as the Mid-360's built-in one or the flight controller's): orientation,
  /// body rates and specific force, in body_frame; ideal (no noise or bias).
  sensor_msgs::Imu imu(const Simulator& sim) const;
  /// The latest completed scan in the LIO frame, when new since the last call.
  std::optional<sensor_msgs::PointCloud2> newScan(const Simulator& sim);
  const LioMessageConfig& config() const { return config_; }

 private:
  LioMessageConfig config_;
  uint64_t last_odom_seq_ = 0, last_scan_seq_ = 0;
};

}  // namespace efs::sim
