// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// ROS wrapper of Se3Controller: odometry drives the control loop (one step per odometry message,
// at most control_rate_hz), a watchdog timer at the same rate keeps commanding when odometry
// stops (the core then levels the attitude and descends). Outputs SO3Command (simulator) and/or
// AttitudeTarget (PX4 via mavros), chosen by `output`. Safety is the core's: stale or NaN
// references hold the latched position, stale odometry descends; mode changes are logged.
#pragma once

#include <explore_from_sketch/PositionCommand.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <map>
#include <optional>
#include <string>
#include <utility>

#include "se3_controller/se3_controller.h"

namespace efs::control {

struct Se3ControllerNodeConfig {
  std::string world_frame = "world";
  bool publish_so3 = true;
  bool publish_attitude = false;
  bool use_imu = false;
  double control_rate_hz = 100.0;
  Se3ControllerConfig controller;
};

Se3ControllerNodeConfig loadSe3ControllerNodeConfig(const ros::NodeHandle& private_nh);

class Se3ControllerNode {
 public:
  Se3ControllerNode(ros::NodeHandle nh, const Se3ControllerNodeConfig& config);

 private:
  void onCommand(const explore_from_sketch::PositionCommand::ConstPtr& msg);
  void onOdom(const nav_msgs::Odometry::ConstPtr& msg);
  void onImu(const sensor_msgs::Imu::ConstPtr& msg);
  void onWatchdog(const ros::TimerEvent&);
  void step(const ros::Time& now);
  /// Warns about a degraded mode at most every kWarningPeriod_s per kind, so that one kind never
  /// hides another.
  void warnThrottledPerKind(const ros::Time& now, const ControlOutput& out);

  static constexpr double kWarningPeriod_s = 0.5;

  Se3ControllerNodeConfig config_;
  Se3Controller controller_;
  OdometryState odom_;
  bool have_odom_msg_ = false;  ///< odom_ holds a received message (not the default state)
  std::optional<ros::WallTime> said_waiting_;  ///< when "no odometry yet" was last said
  FlatReference ref_;
  bool have_ref_ = false;
  std::optional<ros::Time> last_step_, last_imu_;
  std::optional<ControlMode> last_mode_;  ///< unset until the first step, which is always said
  std::map<std::pair<ControlMode, bool>, ros::Time> last_warning_;  ///< by (mode, odom rejected)

  ros::Subscriber cmd_sub_, odom_sub_, imu_sub_;
  ros::Publisher so3_pub_, attitude_pub_;
  ros::Timer watchdog_;
};

}  // namespace efs::control
