// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "lio_bridge_ros/lio_bridge.h"

#include <explore_from_sketch/LioStatus.h>
#include <explore_from_sketch/RegistrationFrame.h>
#include <geometry_msgs/TransformStamped.h>

#include "efs_common_ros/cloud_conversions.h"
#include "efs_common_ros/param_reader.h"
#include "lio_bridge_ros/topics.h"

namespace efs::lio {

LioBridgeConfig loadLioBridgeConfig(const ros::NodeHandle& private_nh) {
  ros_common::ParamReader p(private_nh);
  LioBridgeConfig c;
  p.get("world_frame", c.world_frame);
  p.get("body_frame", c.body_frame);
  p.get("publish_tf", c.publish_tf);
  p.get("gravity_align", c.gravity_align);
  p.get("registration_rate_hz", c.registration_rate_hz);
  p.get("local_map_rate_hz", c.local_map_rate_hz);
  p.get("status_rate_hz", c.status_rate_hz);
  p.get("stale_timeout_s", c.monitor.stale_timeout_s);
  p.get("max_speed_mps", c.monitor.max_speed_mps);
  p.get("min_jump_m", c.monitor.min_jump_m);
  p.get("velocity_window_s", c.velocity.window_s);
  p.get("velocity_fit_order", c.velocity.fit_order);
  p.get("voxel_size_m", c.local_map.voxel_size_m);
  p.get("local_map_radius_m", c.local_map.window_radius_m);
  p.get("max_range_m", c.local_map.max_range_m);
  p.get("gravity_samples", c.gravity.samples_needed);
  p.rejectUnknown();
  requireThat(!c.world_frame.empty(), "world_frame", "must not be empty");
  requireThat(!c.body_frame.empty(), "body_frame", "must not be empty");
  requireInRange("registration_rate_hz", c.registration_rate_hz, 1e-3, 100.0);
  requireInRange("local_map_rate_hz", c.local_map_rate_hz, 1e-3, 100.0);
  requireInRange("status_rate_hz", c.status_rate_hz, 1e-3, 1000.0);
  c.monitor.validate();
  c.velocity.validate();
  c.local_map.validate();
  c.gravity.validate();
  return c;
}

LioBridge::LioBridge(ros::NodeHandle nh, const LioBridgeConfig& config)
    : config_(config),
      monitor_(config.monitor),
      velocity_(config.velocity),
      local_map_(config.local_map),
      decimator_(config.registration_rate_hz),
      aligner_(config.gravity) {
  odom_pub_ = nh.advertise<nav_msgs::Odometry>(topics::kOdom, 50);
  scan_pub_ = nh.advertise<sensor_msgs::PointCloud2>(topics::kScanWorld, 5);
  map_pub_ = nh.advertise<sensor_msgs::PointCloud2>(topics::kLocalMap, 1);
  frame_pub_ = nh.advertise<explore_from_sketch::RegistrationFrame>(topics::kRegistrationFrame, 5);
  status_pub_ = nh.advertise<explore_from_sketch::LioStatus>(topics::kStatus, 5);
  odom_sub_ = nh.subscribe(topics::kLioOdometry, 100, &LioBridge::onOdometry, this);
  cloud_sub_ = nh.subscribe(topics::kLioCloud, 5, &LioBridge::onCloud, this);
  if (config_.gravity_align) imu_sub_ = nh.subscribe(topics::kImu, 400, &LioBridge::onImu, this);
  status_timer_ =
      nh.createTimer(ros::Duration(1.0 / config_.status_rate_hz), &LioBridge::onStatusTimer, this);
  map_timer_ = nh.createTimer(ros::Duration(1.0 / config_.local_map_rate_hz),
                              &LioBridge::onLocalMapTimer, this);
}

Eigen::Quaterniond LioBridge::alignment() const {
  return aligned_ ? *aligned_ : Eigen::Quaterniond::Identity();
}

void LioBridge::reject(const std::string& why) {
  last_problem_ = why;
  ROS_WARN_THROTTLE(1.0, "lio_bridge: %s", why.c_str());
}

void LioBridge::onImu(const sensor_msgs::Imu::ConstPtr& msg) {
  if (aligned_) return;
  aligner_.add(
      {msg->linear_acceleration.x, msg->linear_acceleration.y, msg->linear_acceleration.z});
  if (aligner_.moved()) {
    reject("gravity alignment: the vehicle moved during the still period; restarting");
    aligner_.reset();
  } else if (const auto r = aligner_.rotation()) {
    aligned_ = r;
    ROS_INFO("lio_bridge: gravity aligned (tilt %.2f deg)",
             Eigen::AngleAxisd(*r).angle() * 180.0 / M_PI);
  }
}

void LioBridge::onOdometry(const nav_msgs::Odometry::ConstPtr& msg) {
  if (!ready()) return;
  OdometrySample s;
  s.stamp_s = msg->header.stamp.toSec();
  const auto& p = msg->pose.pose.position;
  const auto& q = msg->pose.pose.orientation;
  const Eigen::Quaterniond r = alignment();
  s.p_world_m = r * Eigen::Vector3d(p.x, p.y, p.z);
  s.q_world_body = r * Eigen::Quaterniond(q.w, q.x, q.y, q.z);
  const InputMonitor::Result verdict = monitor_.check(s);
  if (verdict.verdict == InputMonitor::Verdict::kRejected) {
    reject(verdict.reason);
    return;
  }
  if (verdict.verdict == InputMonitor::Verdict::kJump) {
    reject(verdict.reason);
    velocity_.reset();  // follow the new pose; differences across the jump are meaningless
  }
  velocity_.add(s.stamp_s, s.p_world_m);
  const Eigen::Vector3d v = velocity_.velocity();

  nav_msgs::Odometry out;
  out.header.stamp = msg->header.stamp;
  out.header.frame_id = config_.world_frame;
  out.child_frame_id = config_.body_frame;
  out.pose.pose.position.x = s.p_world_m.x();
  out.pose.pose.position.y = s.p_world_m.y();
  out.pose.pose.position.z = s.p_world_m.z();
  const Eigen::Quaterniond qn = s.q_world_body.normalized();
  out.pose.pose.orientation.w = qn.w();
  out.pose.pose.orientation.x = qn.x();
  out.pose.pose.orientation.y = qn.y();
  out.pose.pose.orientation.z = qn.z();
  out.pose.covariance = msg->pose.covariance;
  // REP 103: twist is in the child (body) frame.
  const Eigen::Vector3d v_body = qn.inverse() * v;
  out.twist.twist.linear.x = v_body.x();
  out.twist.twist.linear.y = v_body.y();
  out.twist.twist.linear.z = v_body.z();
  out.twist.twist.angular = msg->twist.twist.angular;
  odom_pub_.publish(out);

  if (config_.publish_tf) {
    geometry_msgs::TransformStamped t;
    t.header = out.header;
    t.child_frame_id = config_.body_frame;
    t.transform.translation.x = s.p_world_m.x();
    t.transform.translation.y = s.p_world_m.y();
    t.transform.translation.z = s.p_world_m.z();
    t.transform.rotation = out.pose.pose.orientation;
    tf_.sendTransform(t);
  }
}

void LioBridge::onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  if (!ready()) return;
  const auto& last = monitor_.last();
  if (!last) {
    reject("cloud ignored: no accepted odometry yet");
    return;
  }
  std::vector<Eigen::Vector3f> pts;
  try {
    pts = ros_common::fromPointCloud2(*msg);
  } catch (const std::exception& e) {
    reject(std::string("cloud rejected: ") + e.what());
    return;
  }
  if (pts.empty()) {
    reject("cloud rejected: empty");
    return;
  }
  if (aligned_) {
    const Eigen::Matrix3f r = aligned_->toRotationMatrix().cast<float>();
    for (auto& p : pts) p = r * p;
  }
  size_t finite = 0;
  for (const auto& p : pts) finite += p.allFinite();
  if (finite < pts.size()) {
    reject("cloud: " + std::to_string(pts.size() - finite) + " of " + std::to_string(pts.size()) +
           " points are not finite and were dropped");
    std::vector<Eigen::Vector3f> kept;
    kept.reserve(finite);
    for (const auto& p : pts) {
      if (p.allFinite()) kept.push_back(p);
    }
    pts.swap(kept);
  }
  local_map_.insert(pts, last->p_world_m);
  local_map_.crop(last->p_world_m);

  std_msgs::Header header;
  header.stamp = msg->header.stamp;
  header.frame_id = config_.world_frame;
  scan_pub_.publish(ros_common::toPointCloud2(pts, header));

  if (decimator_.due(header.stamp.toSec())) {
    explore_from_sketch::RegistrationFrame frame;
    frame.header = header;
    frame.robot_position.x = last->p_world_m.x();
    frame.robot_position.y = last->p_world_m.y();
    frame.robot_position.z = last->p_world_m.z();
    frame.local_map = ros_common::toPointCloud2(local_map_.points(), header);
    frame_pub_.publish(frame);
  }
}

void LioBridge::onLocalMapTimer(const ros::TimerEvent&) {
  if (map_pub_.getNumSubscribers() == 0 || local_map_.size() == 0) return;
  std_msgs::Header header;
  header.stamp = ros::Time::now();
  header.frame_id = config_.world_frame;
  map_pub_.publish(ros_common::toPointCloud2(local_map_.points(), header));
}

void LioBridge::onStatusTimer(const ros::TimerEvent&) {
  explore_from_sketch::LioStatus s;
  s.header.stamp = ros::Time::now();
  const InputHealth h = monitor_.health(s.header.stamp.toSec());
  s.health = h == InputHealth::kHealthy ? explore_from_sketch::LioStatus::HEALTHY
             : h == InputHealth::kStale ? explore_from_sketch::LioStatus::STALE
                                        : explore_from_sketch::LioStatus::NO_DATA;
  if (h == InputHealth::kStale) ROS_WARN_THROTTLE(2.0, "lio_bridge: odometry is stale");
  s.last_problem = last_problem_;
  s.rejected_count = static_cast<uint32_t>(monitor_.rejectedCount());
  s.jump_count = static_cast<uint32_t>(monitor_.jumpCount());
  status_pub_.publish(s);
}

}  // namespace efs::lio
