// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "se3_controller_ros/se3_controller_node.h"

#include <explore_from_sketch/AttitudeTarget.h>
#include <explore_from_sketch/SO3Command.h>
#include <tf2_eigen/tf2_eigen.h>

#include <vector>

#include "efs_common_ros/param_reader.h"
#include "se3_controller_ros/topics.h"

namespace efs::control {

namespace {

void getVector3(ros_common::ParamReader& p, const ros::NodeHandle& nh, const std::string& key,
                Eigen::Vector3d& value) {
  std::vector<double> v{value.x(), value.y(), value.z()};
  p.get(key, v);
  if (v.size() != 3)
    throw ConfigError("parameter '" + nh.resolveName(key) + "' must have 3 elements, has " +
                      std::to_string(v.size()));
  value = {v[0], v[1], v[2]};
}

geometry_msgs::Vector3 vec(const Eigen::Vector3d& v) {
  geometry_msgs::Vector3 q;
  return tf2::toMsg(v, q);
}

geometry_msgs::Quaternion quat(const Eigen::Quaterniond& q) { return tf2::toMsg(q); }

}  // namespace

Se3ControllerNodeConfig loadSe3ControllerNodeConfig(const ros::NodeHandle& private_nh) {
  ros_common::ParamReader p(private_nh);
  Se3ControllerNodeConfig c;
  Se3ControllerConfig& k = c.controller;
  std::string output = "so3";
  p.get("world_frame", c.world_frame);
  p.get("output", output);
  p.get("use_imu", c.use_imu);
  p.get("control_rate_hz", c.control_rate_hz);
  p.get("mass_kg", k.mass_kg);
  p.get("gravity_mps2", k.gravity_mps2);
  getVector3(p, private_nh, "kp_position", k.kp_position);
  getVector3(p, private_nh, "kv_velocity", k.kv_velocity);
  p.get("max_position_error_m", k.max_position_error_m);
  p.get("max_tilt_rad", k.max_tilt_rad);
  p.get("min_thrust_accel_mps2", k.min_thrust_accel_mps2);
  getVector3(p, private_nh, "kR", k.kR);
  getVector3(p, private_nh, "kOm", k.kOm);
  p.get("use_feedforward", k.use_feedforward);
  p.get("odom_timeout_s", k.odom_timeout_s);
  p.get("command_timeout_s", k.command_timeout_s);
  p.get("feedforward_on_odometry_loss_s", k.feedforward_on_odometry_loss_s);
  p.get("dead_reckoning_lag_s", k.dead_reckoning_lag_s);
  p.get("imu_max_age_s", k.imu_max_age_s);
  p.get("brake_accel_mps2", k.brake_accel_mps2);
  p.get("brake_attitude_lag_s", k.brake_attitude_lag_s);
  p.get("descent_delay_s", k.descent_delay_s);
  p.get("descent_accel_mps2", k.descent_accel_mps2);
  p.get("descent_speed_mps", k.descent_speed_mps);
  p.get("hover_throttle_initial", k.hover_throttle_initial);
  p.get("hover_throttle_min", k.hover_throttle_min);
  p.get("hover_throttle_max", k.hover_throttle_max);
  p.get("hover_estimator_time_constant_s", k.hover_estimator_time_constant_s);
  p.rejectUnknown();
  requireThat(!c.world_frame.empty(), "world_frame", "must not be empty");
  requireThat(output == "so3" || output == "attitude" || output == "both", "output",
              "must be \"so3\", \"attitude\" or \"both\", not \"" + output + "\"");
  c.publish_so3 = output != "attitude";
  c.publish_attitude = output != "so3";
  requireInRange("control_rate_hz", c.control_rate_hz, 1.0, 1000.0);
  k.validate();
  return c;
}

Se3ControllerNode::Se3ControllerNode(ros::NodeHandle nh, const Se3ControllerNodeConfig& config)
    : config_(config), controller_(config.controller) {
  if (config_.publish_so3)
    so3_pub_ = nh.advertise<explore_from_sketch::SO3Command>(topics::kSo3Command, 10);
  if (config_.publish_attitude)
    attitude_pub_ = nh.advertise<explore_from_sketch::AttitudeTarget>(topics::kAttitudeTarget, 10);
  cmd_sub_ = nh.subscribe(topics::kPositionCommand, 10, &Se3ControllerNode::onCommand, this);
  odom_sub_ = nh.subscribe(topics::kOdom, 10, &Se3ControllerNode::onOdom, this,
                           ros::TransportHints().tcpNoDelay());
  if (config_.use_imu) imu_sub_ = nh.subscribe(topics::kImu, 50, &Se3ControllerNode::onImu, this);
  watchdog_ = nh.createTimer(ros::Duration(1.0 / config_.control_rate_hz),
                             &Se3ControllerNode::onWatchdog, this);
}

void Se3ControllerNode::onCommand(const explore_from_sketch::PositionCommand::ConstPtr& msg) {
  FlatReference r;
  r.stamp_s = msg->header.stamp.isZero() ? ros::Time::now().toSec() : msg->header.stamp.toSec();
  r.p_world_m = {msg->position.x, msg->position.y, msg->position.z};
  r.v_world_mps = {msg->velocity.x, msg->velocity.y, msg->velocity.z};
  r.a_world_mps2 = {msg->acceleration.x, msg->acceleration.y, msg->acceleration.z};
  r.j_world_mps3 = {msg->jerk.x, msg->jerk.y, msg->jerk.z};
  r.yaw_rad = msg->yaw;
  r.yaw_rate_radps = msg->yaw_dot;
  ref_ = r;  // a non-finite command is refused by the controller, which then holds
  have_ref_ = true;
}

void Se3ControllerNode::onOdom(const nav_msgs::Odometry::ConstPtr& msg) {
  OdometryState o;
  o.stamp_s = msg->header.stamp.isZero() ? ros::Time::now().toSec() : msg->header.stamp.toSec();
  const auto& p = msg->pose.pose.position;
  const auto& q = msg->pose.pose.orientation;
  const auto& v = msg->twist.twist.linear;
  const auto& w = msg->twist.twist.angular;
  o.p_world_m = {p.x, p.y, p.z};
  o.q_world_body = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
  // REP 103: the twist is in the child (body) frame.
  o.v_world_mps = o.q_world_body.normalized() * Eigen::Vector3d(v.x, v.y, v.z);
  o.omega_body_radps = {w.x, w.y, w.z};
  // Without an IMU the hover-throttle estimate learns from the odometry's velocity changes.
  const double dt = o.stamp_s - odom_.stamp_s;
  if (!config_.use_imu && dt >= 0.005 && dt <= 0.1) {
    o.has_acceleration = true;
    o.a_world_mps2 = (o.v_world_mps - odom_.v_world_mps) / dt;
  }
  odom_ = o;
  have_odom_msg_ = true;
  const ros::Time now = ros::Time::now();
  if (last_step_ && (now - *last_step_).toSec() < 0.9 / config_.control_rate_hz) return;
  step(now);
}

void Se3ControllerNode::onImu(const sensor_msgs::Imu::ConstPtr& msg) {
  const ros::Time stamp = msg->header.stamp.isZero() ? ros::Time::now() : msg->header.stamp;
  const auto& f = msg->linear_acceleration;
  const Eigen::Vector3d f_body(f.x, f.y, f.z);
  // Without its own orientation the IMU is rotated by the odometry's; none yet, no use.
  if (msg->orientation_covariance[0] < 0.0 && !have_odom_msg_) return;
  Eigen::Quaterniond q = odom_.q_world_body;
  if (msg->orientation_covariance[0] >= 0.0) {
    const auto& m = msg->orientation;
    q = Eigen::Quaterniond(m.w, m.x, m.y, m.z);
  }
  if (last_imu_ && f_body.allFinite() && q.coeffs().allFinite() && q.norm() > 0.5) {
    const double dt = (stamp - *last_imu_).toSec();
    const Eigen::Vector3d a_world =
        q.normalized() * f_body - config_.controller.gravity_mps2 * Eigen::Vector3d::UnitZ();
    if (dt > 0.0 && dt < 0.5) controller_.observeAcceleration(a_world, q.normalized(), dt);
    controller_.observeImu(a_world, stamp.toSec());
  }
  last_imu_ = stamp;
}

void Se3ControllerNode::onWatchdog(const ros::TimerEvent&) {
  const ros::Time now = ros::Time::now();
  if (last_step_ && (now - *last_step_).toSec() < 1.5 / config_.control_rate_hz) return;
  step(now);  // odometry is late: the controller sees it stale and acts on it
}

void Se3ControllerNode::warnThrottledPerKind(const ros::Time& now, const ControlOutput& out) {
  // One throttle per kind (mode, odometry rejected or not): a stale-odometry descent warned about
  // just before must not hide the hold that follows it.
  const auto kind = std::make_pair(out.mode, out.odometry_rejected);
  const auto it = last_warning_.find(kind);
  if (it != last_warning_.end() && (now - it->second).toSec() >= 0.0 &&
      (now - it->second).toSec() < kWarningPeriod_s)
    return;
  last_warning_[kind] = now;
  ROS_WARN("se3_controller: %s: %s", toString(out.mode), out.reason.c_str());
}

void Se3ControllerNode::step(const ros::Time& now) {
  last_step_ = now;
  if (!have_odom_msg_) {
    // odom_ is a placeholder until then: a vehicle "at the origin, at rest" would be commanded
    // toward the origin (seen: a simulated vehicle starting in hover at 10 m dived into the floor).
    // Wall time: before the first odometry a simulated clock may not run yet.
    const ros::WallTime wall = ros::WallTime::now();
    if (!said_waiting_ || (wall - *said_waiting_).toSec() >= 1.0) {
      ROS_WARN("se3_controller: no_odometry: no valid odometry yet: commanding nothing");
      said_waiting_ = wall;
    }
    return;
  }
  const ControlOutput out = controller_.update(
      odom_, have_ref_ ? std::optional<FlatReference>(ref_) : std::nullopt, now.toSec());
  if (out.mode != last_mode_ || out.odometry_rejected) {
    if (out.mode == ControlMode::kTracking && !out.odometry_rejected)
      ROS_INFO("se3_controller: tracking");
    else
      warnThrottledPerKind(now, out);
    last_mode_ = out.mode;
  }
  // Nothing to command from: stay silent rather than send "motors off" to a vehicle that may be
  // in the air (a simulator starting in hover, this node restarted in flight). A flight
  // controller whose setpoint stream stops falls back to its own failsafe.
  if (out.mode == ControlMode::kNoOdometry) return;
  std_msgs::Header h;
  h.stamp = now;
  h.frame_id = config_.world_frame;
  if (config_.publish_so3) {
    explore_from_sketch::SO3Command m;
    m.header = h;
    m.force = vec(out.so3.force_world_N);
    m.orientation = quat(out.so3.orientation);
    for (int i = 0; i < 3; ++i) {
      m.kR[i] = out.so3.kR(i);
      m.kOm[i] = out.so3.kOm(i);
    }
    m.aux.current_yaw = out.so3.current_yaw_rad;
    m.aux.kf_correction = out.so3.kf_correction;
    m.aux.angle_corrections[0] = out.so3.angle_corrections[0];
    m.aux.angle_corrections[1] = out.so3.angle_corrections[1];
    m.aux.enable_motors = out.so3.enable_motors;
    m.aux.use_external_yaw = out.so3.use_external_yaw;
    so3_pub_.publish(m);
  }
  if (config_.publish_attitude) {
    explore_from_sketch::AttitudeTarget m;
    m.header = h;
    m.type_mask = out.attitude.type_mask;
    m.orientation = quat(out.attitude.orientation);
    m.body_rate = vec(out.attitude.body_rate_radps);
    m.thrust = static_cast<float>(out.attitude.thrust);
    attitude_pub_.publish(m);
  }
}

}  // namespace efs::control
