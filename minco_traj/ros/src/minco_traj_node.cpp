// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj_ros/minco_traj_node.h"

#include <Eigen/Geometry>
#include <cmath>

#include "efs_common_ros/cloud_conversions.h"
#include "efs_common_ros/param_reader.h"
#include "efs_common_ros/position_history_params.h"
#include "minco_traj_ros/topics.h"
#include "minco_traj_ros/traj_messages.h"

namespace efs::traj {

MincoTrajNodeConfig loadMincoTrajNodeConfig(const ros::NodeHandle& private_nh) {
  ros_common::ParamReader p(private_nh);
  MincoTrajNodeConfig c;
  TrajectoryServerConfig& s = c.server;
  p.get("world_frame", c.world_frame);
  p.get("command_rate_hz", c.command_rate_hz);
  p.get("odom_timeout_s", c.odom_timeout_s);
  p.get("look_at_distance_m", c.look_at_distance_m);
  p.get("marker_dt_s", c.marker_dt_s);
  c.scan_origin = ros_common::readPositionHistoryConfig(p, "scan_origin");
  p.get("replan_period_s", s.replan_period_s);
  p.get("replan_horizon_remaining_s", s.replan_horizon_remaining_s);
  p.get("collision_check_horizon_s", s.collision_check_horizon_s);
  p.get("collision_check_clearance_m", s.collision_check_clearance_m);
  p.get("goal_reached_m", s.goal_reached_m);
  p.get("plan_from_future_s", s.plan_from_future_s);
  p.get("max_tracking_error_m", s.max_tracking_error_m);
  p.get("retry_after_failed_plan_s", s.retry_after_failed_plan_s);
  p.get("max_retry_backoff_s", s.max_retry_backoff_s);
  p.get("new_question_distance_m", s.new_question_distance_m);
  p.get("give_up_after_failed_plans", s.give_up_after_failed_plans);
  p.get("recenter_distance_m", s.recenter_distance_m);
  p.get("grid/resolution_m", s.grid.resolution_m);
  p.get("grid/size_x_m", s.grid.size_x_m);
  p.get("grid/size_y_m", s.grid.size_y_m);
  p.get("grid/size_z_m", s.grid.size_z_m);
  p.get("grid/inflation_radius_m", s.grid.inflation_radius_m);
  p.get("grid/max_ray_length_m", s.grid.max_ray_length_m);
  p.get("grid/ray_downsample_m", s.grid.ray_downsample_m);
  p.get("grid/memory_radius_m", s.grid.memory_radius_m);
  p.get("astar/unknown_is_free", s.planner.astar.unknown_is_free);
  p.get("astar/goal_search_radius_m", s.planner.astar.goal_search_radius_m);
  p.get("astar/start_escape_radius_m", s.planner.astar.start_escape_radius_m);
  p.get("astar/heuristic_weight", s.planner.astar.heuristic_weight);
  p.get("astar/unknown_cost_factor", s.planner.astar.unknown_cost_factor);
  p.get("astar/unknown_height_margin_m", s.planner.astar.unknown_height_margin_m);
  p.get("corridor/clearance_m", s.planner.corridor.clearance_m);
  p.get("corridor/box_margin_m", s.planner.corridor.box_margin_m);
  p.get("corridor/max_seed_length_m", s.planner.corridor.max_seed_length_m);
  p.get("corridor/blind_depth_m", s.planner.corridor.blind_depth_m);
  p.get("optimizer/v_max_mps", s.planner.optimizer.v_max_mps);
  p.get("optimizer/a_max_mps2", s.planner.optimizer.a_max_mps2);
  p.get("optimizer/weight_time", s.planner.optimizer.weight_time);
  p.get("yaw/yaw_rate_max_radps", s.planner.yaw.yaw_rate_max_radps);
  p.get("yaw/yaw_acc_max_radps2", s.planner.yaw.yaw_acc_max_radps2);
  p.get("emergency_decel_mps2", s.planner.emergency_decel_mps2);
  p.get("braking_first_min_speed_mps", s.planner.braking_first_min_speed_mps);
  p.get("braking_first_decel_fraction", s.planner.braking_first_decel_fraction);
  p.get("narrow_clearance_m", s.planner.narrow_clearance_m);
  p.get("narrow_v_max_mps", s.planner.narrow_v_max_mps);
  p.get("narrow_corridor_tolerance_m", s.planner.narrow_corridor_tolerance_m);
  p.rejectUnknown();
  requireThat(!c.world_frame.empty(), "world_frame", "must not be empty");
  requireInRange("command_rate_hz", c.command_rate_hz, 1.0, 1000.0);
  requireInRange("odom_timeout_s", c.odom_timeout_s, 1e-3, 10.0);
  requireInRange("look_at_distance_m", c.look_at_distance_m, 1.0, 1e6);
  requireInRange("marker_dt_s", c.marker_dt_s, 1e-3, 10.0);
  s.validate();
  return c;
}

MincoTrajNode::MincoTrajNode(ros::NodeHandle nh, const MincoTrajNodeConfig& config)
    : config_(config), server_(config.server), positions_(config.scan_origin) {
  traj_pub_ = nh.advertise<explore_from_sketch::PolynomialTrajectory>(topics::kTrajectory, 5, true);
  cmd_pub_ = nh.advertise<explore_from_sketch::PositionCommand>(topics::kPositionCommand, 10);
  marker_pub_ = nh.advertise<visualization_msgs::MarkerArray>(topics::kMarkers, 2, true);
  unreachable_pub_ = nh.advertise<geometry_msgs::PointStamped>(topics::kUnreachableGoal, 5);
  scan_sub_ = nh.subscribe(topics::kScanWorld, 5, &MincoTrajNode::onScan, this);
  ros::SubscribeOptions odom_options = ros::SubscribeOptions::create<nav_msgs::Odometry>(
      topics::kOdom, 50, [this](const nav_msgs::Odometry::ConstPtr& m) { onOdom(m); },
      ros::VoidPtr(), &odom_queue_);
  odom_sub_ = nh.subscribe(odom_options);
  target_sub_ = nh.subscribe(topics::kTarget, 5, &MincoTrajNode::onTarget, this);
  const ros::Duration period(1.0 / config_.command_rate_hz);
  plan_timer_ = nh.createTimer(period, &MincoTrajNode::onPlanTimer, this);
  ros::TimerOptions command_options(
      period, [this](const ros::TimerEvent& e) { onCommandTimer(e); }, &command_queue_);
  command_timer_ = nh.createTimer(command_options);
  odom_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &odom_queue_);
  odom_spinner_->start();
  command_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &command_queue_);
  command_spinner_->start();
}

MincoTrajNode::~MincoTrajNode() {
  command_timer_.stop();
  if (command_spinner_) command_spinner_->stop();
  odom_sub_.shutdown();
  if (odom_spinner_) odom_spinner_->stop();
}

void MincoTrajNode::refreshCommandSource() {
  const bool stopping = server_.stopping();
  {
    std::lock_guard<std::mutex> lock(command_mutex_);
    if (command_source_ && command_source_revision_ == server_.track().revision() &&
        command_source_->stopping == stopping && command_source_->goal_reached == goal_reached_ &&
        command_source_->trajectory_id == trajectory_id_)
      return;
  }
  // The copy is made outside the lock; the command thread keeps sampling the old one meanwhile.
  auto fresh = std::make_shared<CommandSource>();
  fresh->track = server_.track();
  fresh->stopping = stopping;
  fresh->goal_reached = goal_reached_;
  fresh->trajectory_id = trajectory_id_;
  std::lock_guard<std::mutex> lock(command_mutex_);
  command_source_ = std::move(fresh);
  command_source_revision_ = server_.track().revision();
}

std::pair<std::optional<VehicleState>, ros::Time> MincoTrajNode::latestState() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return {state_, state_stamp_};
}

void MincoTrajNode::onScan(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  // Unstamped like unstamped odometry: taken as now.
  const ros::Time stamp = msg->header.stamp.isZero() ? ros::Time::now() : msg->header.stamp;
  std::optional<Eigen::Vector3d> origin;
  std::string why;
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    origin = positions_.at(stamp.toSec(), &why);
  }
  if (!origin) {
    ROS_WARN_THROTTLE(1.0,
                      "minco_traj: scan ignored: the sensor position at its stamp is unknown: %s",
                      why.c_str());
    return;
  }
  std::vector<Eigen::Vector3f> points;
  try {
    points = ros_common::fromPointCloud2(*msg);
  } catch (const std::exception& e) {
    ROS_WARN_THROTTLE(1.0, "minco_traj: scan rejected: %s", e.what());
    return;
  }
  server_.insertScan(*origin, points);
}

void MincoTrajNode::onOdom(const nav_msgs::Odometry::ConstPtr& msg) {
  VehicleState s;
  const auto& p = msg->pose.pose.position;
  const auto& q = msg->pose.pose.orientation;
  const auto& v = msg->twist.twist.linear;
  s.p_world_m = {p.x, p.y, p.z};
  // REP 103: the twist is in the child (body) frame.
  s.v_world_mps =
      Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized() * Eigen::Vector3d(v.x, v.y, v.z);
  s.yaw_rad = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
  if (!s.p_world_m.allFinite() || !s.v_world_mps.allFinite() || !std::isfinite(s.yaw_rad)) {
    ROS_WARN_THROTTLE(1.0, "minco_traj: odometry rejected: non-finite pose or twist");
    return;
  }
  std::lock_guard<std::mutex> lock(state_mutex_);
  state_ = s;
  state_stamp_ = msg->header.stamp.isZero() ? ros::Time::now() : msg->header.stamp;
  positions_.add(state_stamp_.toSec(), s.p_world_m);
}

void MincoTrajNode::onTarget(const geometry_msgs::PoseStamped::ConstPtr& msg) {
  const auto& p = msg->pose.position;
  const auto& q = msg->pose.orientation;
  const Eigen::Vector3d goal(p.x, p.y, p.z);
  std::optional<Eigen::Vector3d> look_at;
  const double qn = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (std::isfinite(qn) && qn > 1e-6) {  // an all-zero orientation means "look at the goal"
    const double yaw =
        std::atan2(2.0 * (q.w * q.z + q.x * q.y), q.w * q.w + q.x * q.x - q.y * q.y - q.z * q.z);
    look_at = goal + config_.look_at_distance_m * Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0);
  } else if (!std::isfinite(qn)) {
    look_at = Eigen::Vector3d::Constant(qn);  // rejected below with the goal
  }
  const ServerEvent e = server_.setGoal(goal, look_at, ros::Time::now().toSec());
  if (e == ServerEvent::kSameGoal) return;  // the planner's timer repeating its target
  if (e == ServerEvent::kRejectedInput) {
    ROS_WARN("minco_traj: target rejected: %s", server_.lastMessage().c_str());
    return;
  }
  goal_reached_ = false;
  refreshCommandSource();
  ROS_INFO("minco_traj: %s", server_.lastMessage().c_str());
}

void MincoTrajNode::onPlanTimer(const ros::TimerEvent&) {
  const ros::Time now = ros::Time::now();
  const double t = now.toSec();
  const auto [state, state_stamp] = latestState();
  if (state && (now - state_stamp).toSec() <= config_.odom_timeout_s) {
    if (server_.holdingAlongPath()) {
      server_.resumeFromHold(t);
      ROS_WARN("minco_traj: %s", server_.lastMessage().c_str());
    }
    const ServerEvent e = server_.update(t, *state);
    if (e == ServerEvent::kReplanned || e == ServerEvent::kEmergencyStop) publishTrajectory(now, e);
    if (e == ServerEvent::kEmergencyStop)
      ROS_WARN("minco_traj: emergency stop: %s", server_.lastMessage().c_str());
    if (e == ServerEvent::kPlanFailedKeptCourse)
      ROS_WARN_THROTTLE(1.0, "minco_traj: %s", server_.lastMessage().c_str());
    if (e == ServerEvent::kRejectedInput)
      ROS_WARN_THROTTLE(1.0, "minco_traj: %s", server_.lastMessage().c_str());
    if (e == ServerEvent::kGoalReached) {
      goal_reached_ = true;
      ROS_INFO("minco_traj: %s", server_.lastMessage().c_str());
    }
    publishGoalFailure(now);
  } else if (state && !server_.holdingAlongPath() && server_.current()) {
    // Odometry lost in flight: the reference stops on the checked path instead of running on.
    server_.holdAlongPath(t);
    ROS_WARN("minco_traj: no odometry for %.2f s: %s", (now - state_stamp).toSec(),
             server_.lastMessage().c_str());
  } else if (server_.goal()) {
    ROS_WARN_THROTTLE(1.0, "minco_traj: no recent odometry; not replanning");
  }
  refreshCommandSource();
}

void MincoTrajNode::onCommandTimer(const ros::TimerEvent&) {
  std::shared_ptr<const CommandSource> source;
  {
    std::lock_guard<std::mutex> lock(command_mutex_);
    source = command_source_;
  }
  if (!source) return;
  const ros::Time now = ros::Time::now();
  const std::optional<ReferenceSample> s = source->track.at(now.toSec());
  if (!s || !s->valid) return;
  std_msgs::Header h;
  h.stamp = now;
  h.frame_id = config_.world_frame;
  using Cmd = explore_from_sketch::PositionCommand;
  const uint8_t flag = source->stopping       ? Cmd::TRAJECTROY_STATUS_ABORT
                       : source->goal_reached ? Cmd::TRAJECTORY_STATUS_COMPLETED
                                              : Cmd::TRAJECTORY_STATUS_READY;
  cmd_pub_.publish(toPositionCommand(*s, source->trajectory_id, flag, h));
}

void MincoTrajNode::publishGoalFailure(const ros::Time& now) {
  const std::optional<GoalFailure>& f = server_.goalFailure();
  if (!f || f->sequence == published_goal_failure_) return;
  published_goal_failure_ = f->sequence;
  ROS_WARN("minco_traj: giving up on the goal (%.2f, %.2f, %.2f) after %d failed plans: %s",
           f->goal_world_m.x(), f->goal_world_m.y(), f->goal_world_m.z(), f->failed_plans,
           f->message.c_str());
  geometry_msgs::PointStamped m;
  m.header.stamp = now;
  m.header.frame_id = config_.world_frame;
  m.point.x = f->goal_world_m.x();
  m.point.y = f->goal_world_m.y();
  m.point.z = f->goal_world_m.z();
  unreachable_pub_.publish(m);
}

void MincoTrajNode::publishTrajectory(const ros::Time& now, ServerEvent event) {
  const Trajectory* traj = server_.current();
  if (!traj) return;
  ++trajectory_id_;
  std_msgs::Header h;
  h.stamp = ros::Time(server_.currentStart_s());
  h.frame_id = config_.world_frame;
  traj_pub_.publish(toPolynomialTrajectory(
      *traj, trajectory_id_, h, std::string(toString(event)) + ": " + server_.lastMessage()));
  if (marker_pub_.getNumSubscribers() > 0 && server_.lastPlan()) {
    h.stamp = now;
    marker_pub_.publish(planMarkers(*server_.lastPlan(), *traj, h, config_.marker_dt_s));
  }
}

}  // namespace efs::traj
