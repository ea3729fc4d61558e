// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Adapts a LIO pipeline (FAST-LIO2: /cloud_registered and /Odometry in `camera_init`, or the
// simulator's LIO-shaped output) to the suite: odometry with a velocity estimate, the current
// scan and an accumulated local map in the world frame, decimated registration frames, TF
// world -> base_link, and the input's health. Bad input is refused with a logged reason and the
// node keeps running.
#pragma once

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/transform_broadcaster.h>

#include <optional>
#include <string>

#include "lio_bridge/gravity_alignment.h"
#include "lio_bridge/input_monitor.h"
#include "lio_bridge/local_map.h"
#include "lio_bridge/velocity_estimator.h"

namespace efs::lio {

struct LioBridgeConfig {
  std::string world_frame = "world";
  std::string body_frame = "base_link";
  bool publish_tf = true;
  bool gravity_align = false;  ///< level a tilted camera_init from still IMU samples at start
  double registration_rate_hz = 0.2;
  double local_map_rate_hz = 1.0;
  double status_rate_hz = 10.0;
  InputMonitorConfig monitor;
  VelocityEstimatorConfig velocity;
  LocalMapConfig local_map;
  GravityAlignmentConfig gravity;
};

LioBridgeConfig loadLioBridgeConfig(const ros::NodeHandle& private_nh);

class LioBridge {
 public:
  LioBridge(ros::NodeHandle nh, const LioBridgeConfig& config);

 private:
  void onOdometry(const nav_msgs::Odometry::ConstPtr& msg);
  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg);
  void onImu(const sensor_msgs::Imu::ConstPtr& msg);
  void onStatusTimer(const ros::TimerEvent&);
  void onLocalMapTimer(const ros::TimerEvent&);
  void reject(const std::string& why);
  /// R_world_lio: identity unless gravity alignment is on and done.
  Eigen::Quaterniond alignment() const;
  bool ready() const { return !config_.gravity_align || aligned_.has_value(); }

  LioBridgeConfig config_;
  InputMonitor monitor_;
  VelocityEstimator velocity_;
  LocalMap local_map_;
  FrameDecimator decimator_;
  GravityAligner aligner_;
  std::optional<Eigen::Quaterniond> aligned_;
  std::string last_problem_;

  ros::Subscriber odom_sub_, cloud_sub_, imu_sub_;
  ros::Publisher odom_pub_, scan_pub_, map_pub_, frame_pub_, status_pub_;
  ros::Timer status_timer_, map_timer_;
  tf2_ros::TransformBroadcaster tf_;
};

}  // namespace efs::lio
