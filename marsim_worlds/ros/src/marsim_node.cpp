// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds_ros/marsim_node.h"

#include <explore_from_sketch/SimulatorStatus.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/PointCloud2.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "efs_common/resource_usage.h"
#include "efs_common_ros/cloud_conversions.h"
#include "efs_common_ros/param_reader.h"
#include "marsim_worlds/coverage.h"
#include "marsim_worlds_ros/lio_messages.h"
#include "marsim_worlds_ros/topics.h"

namespace efs::sim {

MarsimNodeConfig loadMarsimNodeConfig(const ros::NodeHandle& private_nh) {
  ros_common::ParamReader p(private_nh);
  MarsimNodeConfig c;
  p.get("world_kind", c.session.world.kind);
  p.get("world_size", c.session.world.size);
  // ROS parameters hold 32-bit ints: seeds are read as int and range-checked.
  auto getSeed = [&p](const std::string& key, uint64_t& seed) {
    int value = static_cast<int>(seed);
    p.get(key, value);
    requireInRange(key, value, 0, 1 << 30);
    seed = static_cast<uint64_t>(value);
  };
  getSeed("world_seed", c.session.world.seed);
  p.get("world_resolution_m", c.session.world.resolution_m);
  p.get("world_sdf", c.session.world.sdf_path);
  p.get("world_mesh", c.session.world.mesh_path);
  p.get("world_pcd", c.session.world.pcd_path);
  p.get("start_index", c.session.start_index);
  p.get("real_time_factor", c.real_time_factor);
  p.get("step_s", c.step_s);
  p.get("max_lag_s", c.max_lag_s);
  p.get("max_duration_s", c.max_duration_s);
  p.get("publish_clock", c.publish_clock);
  p.get("publish_twist", c.messages.publish_twist);
  p.get("lio_frame", c.messages.lio_frame);
  p.get("body_frame", c.messages.body_frame);
  p.get("status_rate_hz", c.status_rate_hz);
  p.get("lio_dropout_start_s", c.lio_dropout_start_s);
  p.get("lio_dropout_duration_s", c.lio_dropout_duration_s);
  p.get("coverage_enabled", c.session.coverage_enabled);
  p.get("coverage_sample_spacing_m", c.session.coverage_sample_spacing_m);
  getSeed("seed", c.session.sim.seed);
  p.get("physics_rate_hz", c.session.sim.physics_rate_hz);
  p.get("odometry_rate_hz", c.session.sim.odometry_rate_hz);
  p.get("vehicle_radius_m", c.session.sim.vehicle_radius_m);
  p.get("lidar_enabled", c.session.sim.lidar_enabled);
  p.get("lidar_range_m", c.session.sim.lidar.max_range_m);
  p.get("lidar_pitch_rad", c.session.sim.lidar.mount_pitch_rad);
  p.get("lidar_range_noise_std_m", c.session.sim.lidar.range_noise_std_m);
  p.get("odometry_position_noise_std_m", c.session.sim.odometry.position_noise_std_m);
  p.get("odometry_position_drift_std_m_per_sqrt_s",
        c.session.sim.odometry.position_drift_std_m_per_sqrt_s);
  p.get("odometry_yaw_drift_std_rad_per_sqrt_s",
        c.session.sim.odometry.yaw_drift_std_rad_per_sqrt_s);
  p.rejectUnknown();

  requireInRange("real_time_factor", c.real_time_factor, 0.0, 10000.0);
  requireInRange("step_s", c.step_s, 1e-4, 0.1);
  requireInRange("max_lag_s", c.max_lag_s, 0.0, 10.0);
  requireInRange("max_duration_s", c.max_duration_s, 0.0, 1e6);
  requireInRange("status_rate_hz", c.status_rate_hz, 0.1, 1000.0);
  requireInRange("lio_dropout_start_s", c.lio_dropout_start_s, 0.0, 1e6);
  requireInRange("lio_dropout_duration_s", c.lio_dropout_duration_s, 0.0, 1e6);
  requireThat(!c.messages.lio_frame.empty() && !c.messages.body_frame.empty(), "lio_frame",
              "frames must not be empty");
  c.session.validate();
  return c;
}

MarsimNode::MarsimNode(ros::NodeHandle nh, const MarsimNodeConfig& config)
    : config_(config),
      session_(config.session),
      sim_(&session_.simulator()),
      lio_messages_(config.messages) {
  if (sim_->coverage()) {
    ROS_INFO(
        "marsim_node: ground-truth surface of %zu voxels in %.1f s, seen from the %zu of %zu "
        "free-space samples the start can reach",
        sim_->coverage()->totalVoxels(), session_.groundTruthSeconds(),
        session_.coverageSamplesReachable(), session_.coverageSamplesTotal());
  }
  cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>(topics::kCloudRegistered, 5);
  odom_pub_ = nh.advertise<nav_msgs::Odometry>(topics::kOdometry, 100);
  truth_pub_ = nh.advertise<nav_msgs::Odometry>(topics::kGroundTruth, 100);
  imu_pub_ = nh.advertise<sensor_msgs::Imu>(topics::kImu, 100);
  status_pub_ = nh.advertise<explore_from_sketch::SimulatorStatus>(topics::kStatus, 10);
  if (config_.publish_clock) clock_pub_ = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
  so3_sub_ = nh.subscribe(topics::kSo3Command, 10, &MarsimNode::onSo3, this);
  attitude_sub_ = nh.subscribe(topics::kAttitudeTarget, 10, &MarsimNode::onAttitude, this);
  const StartPose& start = session_.start();
  ROS_INFO("marsim_node: world %s, start (%.1f, %.1f, %.1f), real-time factor %g",
           config_.session.world.describe().c_str(), start.position_m.x(), start.position_m.y(),
           start.position_m.z(), config_.real_time_factor);
}

void MarsimNode::onSo3(const explore_from_sketch::SO3Command::ConstPtr& msg) {
  SO3Command c;
  c.force_world_N = {msg->force.x, msg->force.y, msg->force.z};
  c.q_world_body_des = Eigen::Quaterniond(msg->orientation.w, msg->orientation.x,
                                          msg->orientation.y, msg->orientation.z);
  c.kR_Nm_per_rad = {msg->kR[0], msg->kR[1], msg->kR[2]};
  c.kOm_Nm_s_per_rad = {msg->kOm[0], msg->kOm[1], msg->kOm[2]};
  const CommandStatus s = sim_->setCommand(c);
  if (!s.accepted) ROS_WARN_THROTTLE(1.0, "marsim_node: so3_cmd rejected: %s", s.reason.c_str());
}

void MarsimNode::onAttitude(const explore_from_sketch::AttitudeTarget::ConstPtr& msg) {
  AttitudeTargetCommand c;
  c.type_mask = msg->type_mask;
  c.q_world_body_des = Eigen::Quaterniond(msg->orientation.w, msg->orientation.x,
                                          msg->orientation.y, msg->orientation.z);
  c.body_rate_des_rad_s = {msg->body_rate.x, msg->body_rate.y, msg->body_rate.z};
  c.thrust_normalized = msg->thrust;
  const CommandStatus s = sim_->setCommand(c);
  if (!s.accepted)
    ROS_WARN_THROTTLE(1.0, "marsim_node: attitude_target rejected: %s", s.reason.c_str());
}

void MarsimNode::publishOutputs(double wall_elapsed_s) {
  const double t = sim_->time_s();
  const ros::Time now(t);
  if (config_.publish_clock) {
    rosgraph_msgs::Clock c;
    c.clock = now;
    clock_pub_.publish(c);
  }
  const bool lio_silent = config_.lio_dropout_duration_s > 0.0 &&
                          t >= config_.lio_dropout_start_s &&
                          t < config_.lio_dropout_start_s + config_.lio_dropout_duration_s;
  if (lio_silent != dropout_reported_) {
    dropout_reported_ = lio_silent;
    ROS_WARN("marsim_node: fault injection: LIO output %s at t = %.2f s",
             lio_silent ? "silent" : "back", t);
  }
  // During a dropout the messages are still produced (their sequence moves on) and discarded.
  auto odom = lio_messages_.newOdometry(*sim_);
  auto scan = lio_messages_.newScan(*sim_);
  if (odom) {
    // The IMU is not part of the LIO output: it keeps coming through a LIO dropout.
    truth_pub_.publish(lio_messages_.groundTruth(*sim_));
    imu_pub_.publish(lio_messages_.imu(*sim_));
  }
  if (lio_silent) {
    odom.reset();
    scan.reset();
  }
  if (odom) {
    odom_pub_.publish(*odom);
    // FAST-LIO2 broadcasts the same pose on TF (camera_init -> body).
    geometry_msgs::TransformStamped tf;
    tf.header = odom->header;
    tf.child_frame_id = odom->child_frame_id;
    tf.transform.translation.x = odom->pose.pose.position.x;
    tf.transform.translation.y = odom->pose.pose.position.y;
    tf.transform.translation.z = odom->pose.pose.position.z;
    tf.transform.rotation = odom->pose.pose.orientation;
    tf_broadcaster_.sendTransform(tf);
  }
  if (scan) cloud_pub_.publish(*scan);
  if (sim_->collided() && !collision_reported_) {
    collision_reported_ = true;
    const auto& c = *sim_->collision();
    ROS_ERROR(
        "marsim_node: COLLISION at t = %.2f s at (%.2f, %.2f, %.2f): the run has failed; the "
        "vehicle is stopped",
        c.stamp_s, c.position_m.x(), c.position_m.y(), c.position_m.z());
  }
  if (t >= next_status_s_) {
    next_status_s_ = t + 1.0 / config_.status_rate_hz;
    explore_from_sketch::SimulatorStatus s;
    s.header.stamp = now;
    s.sim_time = t;
    s.coverage = sim_->coverage() ? sim_->coverage()->fraction() : 0.0;
    s.travelled_distance = sim_->travelledDistance_m();
    s.collided = sim_->collided();
    if (s.collided) {
      s.collision_position.x = sim_->collision()->position_m.x();
      s.collision_position.y = sim_->collision()->position_m.y();
      s.collision_position.z = sim_->collision()->position_m.z();
    }
    s.rejected_commands = sim_->rejectedCommands();
    s.last_rejection = sim_->lastRejection();
    s.real_time_factor = wall_elapsed_s > 0.0 ? t / wall_elapsed_s : 0.0;
    status_pub_.publish(s);
  }
}

void MarsimNode::run() {
  const auto wall_start = std::chrono::steady_clock::now();
  double wall_behind_s = 0.0;  // wall time the simulation gave up on catching up (slow-down)
  double t = 0.0;
  publishOutputs(0.0);
  while (ros::ok()) {
    if (config_.max_duration_s > 0.0 && t >= config_.max_duration_s) {
      ROS_INFO("marsim_node: reached max_duration_s = %.1f s of simulated time",
               config_.max_duration_s);
      break;
    }
    t += config_.step_s;
    sim_->advanceTo(t);
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    publishOutputs(wall_s);
    ros::spinOnce();
    if (config_.real_time_factor > 0.0) {
      const double ahead_s = t / config_.real_time_factor - (wall_s - wall_behind_s);
      if (ahead_s > 0.0) {
        std::this_thread::sleep_for(std::chrono::duration<double>(ahead_s));
      } else {
        if (-ahead_s > config_.max_lag_s) wall_behind_s += -ahead_s - config_.max_lag_s;
        std::this_thread::yield();
      }
    }
  }
}

}  // namespace efs::sim
