// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// ROS face of the simulator: it owns the simulated time (publishes /clock for use_sim_time
// graphs), steps the same Simulator the benchmarks step in-process, and publishes FAST-LIO2-shaped
// output. Commands arrive as SO3Command (MARSIM style) or AttitudeTarget (PX4 through mavros).
#pragma once

#include <explore_from_sketch/AttitudeTarget.h>
#include <explore_from_sketch/SO3Command.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <memory>
#include <string>

#include "marsim_worlds/simulation_session.h"
#include "marsim_worlds_ros/lio_messages.h"

namespace efs::sim {

struct MarsimNodeConfig {
  SimulationSessionConfig session;  ///< world, start pose, coverage, simulator
  double real_time_factor = 1.0;    ///< simulated s per wall s; 0 = as fast as possible
  double step_s = 0.01;             ///< simulated time advanced per loop
  /// Behind the wall clock by more than this, the simulation slows down instead of catching up:
  /// stepping flat out starves the other nodes (the controller) of the CPU, so the vehicle flew
  /// open loop for 0.2 s stretches on a loaded 2-core machine and touched the cave. Each step
  /// also yields the CPU once. [s]
  double max_lag_s = 0.02;
  double max_duration_s = 0.0;      ///< stop after this simulated time; 0 = never
  bool publish_clock = true;
  LioMessageConfig messages;  ///< frames and twist of the FAST-LIO2-shaped output
  double status_rate_hz = 10.0;
  /// Fault injection: the LIO output (cloud_registered, Odometry and its TF) falls silent for
  /// this long from `lio_dropout_start_s` of simulated time on, as when FAST-LIO2 stalls; the
  /// vehicle flies on (ground truth and /clock keep coming). 0 s = no dropout.
  double lio_dropout_start_s = 0.0;
  double lio_dropout_duration_s = 0.0;
};

MarsimNodeConfig loadMarsimNodeConfig(const ros::NodeHandle& private_nh);

class MarsimNode {
 public:
  MarsimNode(ros::NodeHandle nh, const MarsimNodeConfig& config);
  /// Runs until ROS shuts down (or max_duration_s of simulated time).
  void run();

 private:
  void onSo3(const explore_from_sketch::SO3Command::ConstPtr& msg);
  void onAttitude(const explore_from_sketch::AttitudeTarget::ConstPtr& msg);
  void publishOutputs(double wall_elapsed_s);

  MarsimNodeConfig config_;
  SimulationSession session_;
  Simulator* sim_;  ///< session_'s simulator
  ros::Subscriber so3_sub_, attitude_sub_;
  ros::Publisher cloud_pub_, odom_pub_, truth_pub_, imu_pub_, status_pub_, clock_pub_;
  LioMessages lio_messages_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  double next_status_s_ = 0.0;
  bool collision_reported_ = false;
  bool dropout_reported_ = false;
};

}  // namespace efs::sim
