// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds_ros/lio_messages.h"

#include "efs_common_ros/cloud_conversions.h"

namespace efs::sim {

nav_msgs::Odometry toOdometryMsg(const ros::Time& stamp, const std::string& frame,
                                 const std::string& child, const Eigen::Vector3d& p,
                                 const Eigen::Quaterniond& q, const Eigen::Vector3d& v_world,
                                 const Eigen::Vector3d& omega_body, bool with_twist) {
  nav_msgs::Odometry o;
  o.header.stamp = stamp;
  o.header.frame_id = frame;
  o.child_frame_id = child;
  o.pose.pose.position.x = p.x();
  o.pose.pose.position.y = p.y();
  o.pose.pose.position.z = p.z();
  o.pose.pose.orientation.w = q.w();
  o.pose.pose.orientation.x = q.x();
  o.pose.pose.orientation.y = q.y();
  o.pose.pose.orientation.z = q.z();
  if (with_twist) {
    const Eigen::Vector3d v_body = q.inverse() * v_world;
    o.twist.twist.linear.x = v_body.x();
    o.twist.twist.linear.y = v_body.y();
    o.twist.twist.linear.z = v_body.z();
    o.twist.twist.angular.x = omega_body.x();
    o.twist.twist.angular.y = omega_body.y();
    o.twist.twist.angular.z = omega_body.z();
  }
  return o;
}

std::optional<nav_msgs::Odometry> LioMessages::newOdometry(const Simulator& sim) {
  if (sim.odometrySeq() == last_odom_seq_) return std::nullopt;
  last_odom_seq_ = sim.odometrySeq();
  const Odometry& o = sim.latestOdometry();
  return toOdometryMsg(ros::Time(o.stamp_s), config_.lio_frame, config_.body_frame, o.p_world_m,
                       o.q_world_body, o.v_world_m_s, o.omega_body_rad_s, config_.publish_twist);
}

nav_msgs::Odometry LioMessages::groundTruth(const Simulator& sim) const {
  const QuadrotorState& g = sim.groundTruth();
  return toOdometryMsg(ros::Time(sim.time_s()), config_.truth_frame, config_.body_frame,
                       g.p_world_m, g.q_world_body, g.v_world_m_s, g.omega_body_rad_s, true);
}

sensor_msgs::Imu LioMessages::imu(const Simulator& sim) const {
  const QuadrotorState& g = sim.groundTruth();
  const Eigen::Vector3d f = sim.imuSpecificForceBody();
  sensor_msgs::Imu m;
  m.header.stamp = ros::Time(sim.time_s());
  m.header.frame_id = config_.body_frame;
  m.orientation.w = g.q_world_body.w();
  m.orientation.x = g.q_world_body.x();
  m.orientation.y = g.q_world_body.y();
  m.orientation.z = g.q_world_body.z();
  m.angular_velocity.x = g.omega_body_rad_s.x();
  m.angular_velocity.y = g.omega_body_rad_s.y();
  m.angular_velocity.z = g.omega_body_rad_s.z();
  m.linear_acceleration.x = f.x();
  m.linear_acceleration.y = f.y();
  m.linear_acceleration.z = f.z();
  return m;
}

std::optional<sensor_msgs::PointCloud2> LioMessages::newScan(const Simulator& sim) {
  const ScanFrame& scan = sim.latestScan();
  if (scan.seq == 0 || scan.seq == last_scan_seq_) return std::nullopt;
  last_scan_seq_ = scan.seq;
  std_msgs::Header h;
  h.stamp = ros::Time(scan.stamp_end_s);
  h.frame_id = config_.lio_frame;
  return ros_common::toPointCloud2(scan.points_world, h);
}

}  // namespace efs::sim
