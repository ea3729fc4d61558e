// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// ROS wrapper of TrajectoryServer: scans and odometry in, exploration targets in, the current
// PolynomialTrajectory (on every replan), a PositionCommand stream at command_rate_hz (ROS time,
// so simulated time works) and visualisation markers out. Bad input (NaN target, cloud without
// xyz, NaN odometry) is refused with a throttled warning; the node keeps running and keeps
// commanding the last valid reference.
#pragma once

#include <geometry_msgs/PointStamped.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>

#include "efs_common/position_history.h"
#include "minco_traj/trajectory_server.h"

namespace efs::traj {

struct MincoTrajNodeConfig {
  std::string world_frame = "world";
  double command_rate_hz = 100.0;
  double odom_timeout_s = 0.2;         ///< older odometry does not drive replanning
  double look_at_distance_m = 1000.0;  ///< target orientation -> look-at point this far ahead
  double marker_dt_s = 0.05;
  PositionHistoryConfig scan_origin;  ///< where the sensor was at each scan's stamp
  TrajectoryServerConfig server;
};

MincoTrajNodeConfig loadMincoTrajNodeConfig(const ros::NodeHandle& private_nh);

class MincoTrajNode {
 public:
  MincoTrajNode(ros::NodeHandle nh, const MincoTrajNodeConfig& config);
  ~MincoTrajNode();  ///< stops the odometry and command threads before their state goes away
  MincoTrajNode(const MincoTrajNode&) = delete;
  MincoTrajNode& operator=(const MincoTrajNode&) = delete;

 private:
  void onScan(const sensor_msgs::PointCloud2::ConstPtr& msg);
  void onOdom(const nav_msgs::Odometry::ConstPtr& msg);
  void onTarget(const geometry_msgs::PoseStamped::ConstPtr& msg);
  /// Replanning (main queue): TrajectoryServer::update, then a fresh command source if the
  /// reference changed.
  void onPlanTimer(const ros::TimerEvent&);
  /// The PositionCommand stream (its own queue and thread): samples the latest command source.
  void onCommandTimer(const ros::TimerEvent&);
  void refreshCommandSource();
  void publishTrajectory(const ros::Time& now, ServerEvent event);
  /// Publishes a goal the server gave up on, once (GoalFailure::sequence).
  void publishGoalFailure(const ros::Time& now);
  /// The latest odometry and its stamp (written by the odometry thread).
  std::pair<std::optional<VehicleState>, ros::Time> latestState() const;

  MincoTrajNodeConfig config_;
  TrajectoryServer server_;
  // Odometry has its own queue and thread: behind a long scan insertion or replan in the main
  // queue it looked 0.2 s stale to the command timer, which then held the reference for nothing
  // (seen: 10-26 false "odometry lost" holds per mission on a loaded 2-core machine).
  ros::CallbackQueue odom_queue_;
  std::unique_ptr<ros::AsyncSpinner> odom_spinner_;
  mutable std::mutex state_mutex_;
  std::optional<VehicleState> state_;
  ros::Time state_stamp_;
  PositionHistory positions_;  ///< scans are ray cast from here at their own stamps
  uint32_t trajectory_id_ = 0;
  bool goal_reached_ = false;

  /// What the command thread samples: a copy of the server's reference and the status flag.
  struct CommandSource {
    ReferenceTrack track;
    bool stopping = false;
    bool goal_reached = false;
    uint32_t trajectory_id = 0;
  };
  // Commands have their own queue and thread too: sampled in the main queue they stopped for a
  // whole scan insertion or replan (seen: 39 gaps over 0.1 s, up to 0.21 s, in one mission; the
  // controller then pulled toward a reference point left behind).
  ros::CallbackQueue command_queue_;
  std::unique_ptr<ros::AsyncSpinner> command_spinner_;
  mutable std::mutex command_mutex_;
  std::shared_ptr<const CommandSource> command_source_;
  uint64_t command_source_revision_ = 0;

  ros::Subscriber scan_sub_, odom_sub_, target_sub_;
  ros::Publisher traj_pub_, cmd_pub_, marker_pub_, unreachable_pub_;
  uint64_t published_goal_failure_ = 0;
  ros::Timer plan_timer_, command_timer_;
};

}  // namespace efs::traj
