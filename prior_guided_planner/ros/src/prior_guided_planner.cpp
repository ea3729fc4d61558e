// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner_ros/prior_guided_planner.h"

#include <explore_from_sketch/ExplorationStatus.h>
#include <explore_from_sketch/Guidepoints.h>
#include <geometry_msgs/PointStamped.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Path.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "efs_common/config_check.h"
#include "efs_common_ros/cloud_conversions.h"
#include "efs_common_ros/param_reader.h"
#include "efs_common_ros/position_history_params.h"
#include "prior_guided_planner/prior_from_bundle.h"
#include "prior_guided_planner_ros/topics.h"
#include "prior_map_tools/prior_bundle.h"

namespace efs::planner {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

std::optional<Eigen::AlignedBox3d> boundsFrom(const std::vector<double>& lo,
                                              const std::vector<double>& hi) {
  requireThat(lo.size() == hi.size(), "bounds_min_m",
              "bounds_min_m and bounds_max_m must both be empty or both hold x, y, z");
  if (lo.empty()) return std::nullopt;
  requireThat(lo.size() == 3, "bounds_min_m", "must hold exactly x, y, z");
  return Eigen::AlignedBox3d(Eigen::Vector3d(lo[0], lo[1], lo[2]),
                             Eigen::Vector3d(hi[0], hi[1], hi[2]));
}

}  // namespace

PriorGuidedPlannerNodeConfig loadPriorGuidedPlannerConfig(const ros::NodeHandle& private_nh) {
  ros_common::ParamReader p(private_nh);
  PriorGuidedPlannerNodeConfig c;
  ExplorationManagerConfig& e = c.exploration;
  p.get("world_frame", c.world_frame);
  p.get("sketch_frame", c.sketch_frame);
  p.get("prior_bundle_path", c.prior_bundle_path);
  p.get("predicted_free_spacing_m", c.predicted_free_spacing_m);
  p.get("plan_rate_hz", c.plan_rate_hz);
  p.get("odom_timeout_s", c.odom_timeout_s);
  c.scan_origin = ros_common::readPositionHistoryConfig(p, "scan_origin");
  std::string mode = toString(e.planner.mode);
  p.get("mode", mode);
  e.planner.mode = parseBaselineMode(mode, private_nh.resolveName("mode"));
  p.get("replan_period_s", e.replan_period_s);
  p.get("target_reached_m", e.target_reached_m);
  p.get("target_progress_m", e.target_progress_m);
  p.get("target_progress_timeout_s", e.target_progress_timeout_s);
  p.get("unreachable_retry_s", e.unreachable_retry_s);
  p.get("unreachable_attempts", e.unreachable_attempts);
  p.get("finish_confirmation_s", e.finish_confirmation_s);
  p.get("unreachable_near_m", e.unreachable_near_m);
  p.get("skip_looked_at_clusters", e.skip_looked_at_clusters);
  p.get("looked_at_fraction", e.looked_at_fraction);
  p.get("fine_path_resolution_factor", e.fine_path_resolution_factor);
  p.get("opening_search_radius_m", e.openings.search_radius_m);
  p.get("opening_min_cells", e.openings.min_cells);
  p.get("opening_narrow_clearance_m", e.openings.narrow_viewpoint_clearance_m);
  p.get("opening_max_walk_cells", e.openings.max_walk_cells);
  p.get("opening_vouched_min_cells", e.openings.vouched_min_cells);
  p.get("opening_vouched_radius_m", e.openings.vouched_radius_m);
  p.get("opening_vouched_unseen_radius_m", e.openings.vouched_unseen_radius_m);
  p.get("opening_vouched_unseen_fraction", e.openings.vouched_unseen_fraction);
  p.get("near_openings_radius_m", e.near_openings_radius_m);
  p.get("near_openings_min_cells", e.near_openings_min_cells);
  p.get("openings_stay_in_tour", e.openings_stay_in_tour);
  p.get("reached_opening_moved_m", e.reached_openings.moved_m);
  p.get("opening_max_visits", e.reached_openings.max_visits);
  p.get("last_resort_patience_s", e.last_resort_stall.patience_s);
  p.get("last_resort_min_gain_fraction", e.last_resort_stall.min_gain_fraction);
  p.get("max_goal_distance_m", e.max_goal_distance_m);
  p.get("max_goal_climb_m", e.max_goal_climb_m);
  p.get("tour_lookahead_m", e.tour_lookahead_m);
  std::vector<double> lo, hi;
  p.get("bounds_min_m", lo);
  p.get("bounds_max_m", hi);
  e.bounds_world_m = boundsFrom(lo, hi);

  double resolution_m = e.observation.resolution_m;
  p.get("map_resolution_m", resolution_m);
  e.observation.resolution_m = e.occupancy.resolution_m = resolution_m;
  double max_range_m = e.observation.max_range_m;
  p.get("max_range_m", max_range_m);
  e.observation.max_range_m = e.occupancy.max_range_m = e.fov.max_range_m = max_range_m;
  p.get("well_observed_distance_m", e.observation.well_observed_distance_m);
  e.viewpoint.useful_range_m = e.observation.well_observed_distance_m;
  p.get("min_view_directions", e.observation.min_view_directions);
  p.get("facing_max_distance_m", e.observation.facing_max_distance_m);
  p.get("facing_min_cosine", e.observation.facing_min_cosine);
  p.get("min_cluster_cells", e.frontier.min_cluster_cells);
  p.get("max_cluster_cells", e.frontier.max_cluster_cells);
  double pitch_deg = e.fov.mount_pitch_rad / kDegToRad;
  p.get("lidar_mount_pitch_deg", pitch_deg);
  e.fov.mount_pitch_rad = pitch_deg * kDegToRad;
  p.get("viewpoint_clearance_m", e.viewpoint.clearance_m);
  p.get("max_viewpoints_per_cluster", e.viewpoint.max_viewpoints_per_cluster);
  p.get("viewpoint_reuse_distance_m", e.viewpoint.reuse_distance_m);
  p.get("vehicle_radius_m", e.path.vehicle_radius_m);
  p.get("path_search_resolution_m", e.path.search_resolution_m);
  p.get("path_narrow_radius_m", e.path.narrow_radius_m);
  p.get("path_narrow_cost_factor", e.path.narrow_cost_factor);

  p.get("rho_m", e.planner.attachment.rho_m);
  p.get("influence_radius_m", e.planner.attachment.influence_radius_m);
  p.get("guidepoint_seen_fraction", e.planner.attachment.seen_fraction);
  p.get("guidepoint_seen_keep_radius_m", e.planner.attachment.seen_keep_radius_m);
  p.get("guidepoint_leftover_detour_m", e.planner.leftover_detour_m);
  p.get("min_confidence", e.planner.min_confidence);
  p.get("tour_searched_viewpoints", e.planner.tour_searched_viewpoints);
  p.get("prior_free_max_viewpoints", e.planner.prior_free_max_viewpoints);
  p.get("v_max_mps", e.planner.fe_tsp.v_max_mps);
  p.get("omega_max_radps", e.planner.fe_tsp.omega_max_radps);
  p.get("beta_e", e.planner.fe_tsp.beta_e);
  p.get("direction_change_cost_s_per_rad", e.planner.fe_tsp.direction_change_cost_s_per_rad);
  p.get("direction_min_speed_mps", e.planner.fe_tsp.direction_min_speed_mps);
  p.get("velocity_change_accel_mps2", e.planner.fe_tsp.velocity_change_accel_mps2);
  p.get("mcts_exploration_constant", e.planner.mcts.exploration_constant);
  p.get("mcts_iterations", e.planner.mcts.iterations);
  p.get("mcts_threads", e.planner.mcts.threads);
  p.get("mcts_reuse_sequences", e.planner.reuse_sequences);
  p.get("warm_start_tours", e.planner.warm_start_tours);
  p.get("warm_start_sequences", e.planner.warm_start_sequences);
  p.get("keep_first_guidepoint_fraction", e.planner.keep_first_guidepoint_fraction);
  p.get("greedy_sensor_range_m", e.planner.greedy.sensor_range_m);
  int max_cells = static_cast<int>(c.markers.max_frontier_cells);
  p.get("max_marker_frontier_cells", max_cells);
  p.get("map_output_dir", c.map_output_dir);
  p.get("map_cloud_voxel_m", c.mission_map.cloud_voxel_m);
  p.get("map_trajectory_spacing_m", c.mission_map.trajectory_spacing_m);
  c.mission_map.max_range_m = max_range_m;
  p.rejectUnknown();

  requireThat(!c.world_frame.empty(), "world_frame", "must not be empty");
  requireThat(!c.sketch_frame.empty(), "sketch_frame", "must not be empty");
  requireInRange("predicted_free_spacing_m", c.predicted_free_spacing_m, 0.05, 100.0);
  requireInRange("plan_rate_hz", c.plan_rate_hz, 1e-3, 100.0);
  requireInRange("odom_timeout_s", c.odom_timeout_s, 1e-3, 3600.0);
  requireInRange("max_marker_frontier_cells", max_cells, 0, 10000000);
  c.markers.max_frontier_cells = static_cast<size_t>(max_cells);
  e.validate();
  c.mission_map.validate();
  return c;
}

PriorGuidedPlannerNode::PriorGuidedPlannerNode(ros::NodeHandle nh,
                                               const PriorGuidedPlannerNodeConfig& config)
    : config_(config), positions_(config.scan_origin) {
  std::optional<GuidepointPrior> prior;
  if (!config_.prior_bundle_path.empty()) {
    try {
      prior = guidepointPriorFromBundle(prior_map::loadPriorBundle(config_.prior_bundle_path),
                                        config_.predicted_free_spacing_m);
    } catch (const std::exception& ex) {
      throw std::runtime_error("prior_bundle_path '" + config_.prior_bundle_path +
                               "': " + ex.what());
    }
    ROS_INFO("prior_guided_planner: prior with %d guidepoints from %s", prior->size(),
             config_.prior_bundle_path.c_str());
  } else {
    ROS_INFO("prior_guided_planner: no prior bundle; exploring prior-free");
  }
  manager_.emplace(config_.exploration, std::move(prior));
  if (!config_.map_output_dir.empty()) {
    mission_map_.emplace(config_.mission_map);
    ROS_INFO(
        "prior_guided_planner: the mission map goes to %s at the end (service %s saves it "
        "now)",
        config_.map_output_dir.c_str(), nh.resolveName(topics::kSaveMap).c_str());
  }

  target_pub_ = nh.advertise<geometry_msgs::PoseStamped>(topics::kTarget, 5);
  look_at_pub_ = nh.advertise<geometry_msgs::PointStamped>(topics::kLookAt, 5);
  tour_pub_ = nh.advertise<nav_msgs::Path>(topics::kTour, 5);
  status_pub_ = nh.advertise<explore_from_sketch::ExplorationStatus>(topics::kStatus, 5);
  guidepoints_pub_ = nh.advertise<explore_from_sketch::Guidepoints>(topics::kGuidepoints, 1, true);
  markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>(topics::kMarkers, 1);
  odom_sub_ = nh.subscribe(topics::kOdom, 50, &PriorGuidedPlannerNode::onOdometry, this);
  scan_sub_ = nh.subscribe(topics::kScanWorld, 5, &PriorGuidedPlannerNode::onScan, this);
  hyp_sub_ = nh.subscribe(topics::kHypotheses, 5, &PriorGuidedPlannerNode::onHypotheses, this);
  unreachable_sub_ =
      nh.subscribe(topics::kUnreachableGoal, 5, &PriorGuidedPlannerNode::onUnreachableGoal, this);
  save_map_srv_ = nh.advertiseService(topics::kSaveMap, &PriorGuidedPlannerNode::onSaveMap, this);
  timer_ = nh.createTimer(ros::Duration(1.0 / config_.plan_rate_hz),
                          &PriorGuidedPlannerNode::onTimer, this);
}

void PriorGuidedPlannerNode::reject(const std::string& why) {
  // A new reason is always said; a repeated one at most once a second.
  const ros::WallTime now = ros::WallTime::now();
  if (why == last_reject_ && (now - last_reject_time_).toSec() < 1.0) return;
  last_reject_ = why;
  last_reject_time_ = now;
  ROS_WARN("prior_guided_planner: %s", why.c_str());
}

bool PriorGuidedPlannerNode::refusedFrame(const std_msgs::Header& header, const std::string& what) {
  if (header.frame_id.empty() || header.frame_id == config_.world_frame) return false;
  reject(what + " refused: frame '" + header.frame_id + "' is not the world frame '" +
         config_.world_frame + "'");
  return true;
}

void PriorGuidedPlannerNode::onOdometry(const nav_msgs::Odometry::ConstPtr& msg) {
  const auto& p = msg->pose.pose.position;
  const auto& q = msg->pose.pose.orientation;
  const Eigen::Vector3d pos(p.x, p.y, p.z);
  const Eigen::Quaterniond quat(q.w, q.x, q.y, q.z);
  if (!pos.allFinite() || !quat.coeffs().allFinite() || quat.norm() < 1e-6) {
    reject("odometry refused: pose is not finite (or a zero quaternion)");
    return;
  }
  if (last_odom_stamp_ && msg->header.stamp < *last_odom_stamp_) {
    reject("odometry refused: went back in time (" + std::to_string(msg->header.stamp.toSec()) +
           " s after " + std::to_string(last_odom_stamp_->toSec()) + " s)");
    return;
  }
  const Eigen::Matrix3d r = quat.normalized().toRotationMatrix();
  RobotPose pose;
  pose.position_world_m = pos;
  pose.yaw_rad = std::atan2(r(1, 0), r(0, 0));
  if (robot_) travelled_m_ += (pos - robot_->position_world_m).norm();
  positions_.add(msg->header.stamp.toSec(), pos);
  // Velocity from the track, not the message's twist: FAST-LIO2 gives it in the body frame and
  // other odometry sources leave it zero. Half a second smooths the controller's jitter.
  constexpr double kVelocityWindow_s = 0.5;
  if (const std::optional<Eigen::Vector3d> v = positions_.velocity(kVelocityWindow_s))
    pose.velocity_world_mps = *v;
  robot_ = pose;
  if (mission_map_) mission_map_->addPose(msg->header.stamp.toSec(), pos, pose.yaw_rad);
  last_odom_stamp_ = msg->header.stamp;
  if (!first_odom_stamp_) first_odom_stamp_ = msg->header.stamp;
}

void PriorGuidedPlannerNode::onScan(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  if (!robot_) {
    reject("scan ignored: no odometry yet (the sensor origin is unknown)");
    return;
  }
  if (refusedFrame(msg->header, "scan")) return;
  std::vector<Eigen::Vector3f> pts;
  try {
    pts = ros_common::fromPointCloud2(*msg);
  } catch (const std::exception& e) {
    reject(std::string("scan refused: ") + e.what());
    return;
  }
  std::string why;
  const std::optional<Eigen::Vector3d> origin = positions_.at(msg->header.stamp.toSec(), &why);
  if (!origin) {
    reject("scan ignored: the sensor position at its stamp is unknown: " + why);
    return;
  }
  const size_t dropped_before = manager_->inputStats().points_dropped_nonfinite;
  manager_->insertScan(*origin, pts);
  if (mission_map_) mission_map_->insertScan(*origin, pts);
  const size_t dropped = manager_->inputStats().points_dropped_nonfinite - dropped_before;
  if (dropped > 0)
    reject("scan: " + std::to_string(dropped) + " of " + std::to_string(pts.size()) +
           " points are not finite and were dropped");
  if (pts.empty()) reject("scan ignored: empty");
}

void PriorGuidedPlannerNode::onHypotheses(
    const explore_from_sketch::RegistrationHypotheses::ConstPtr& msg) {
  if (!msg->header.frame_id.empty() && msg->header.frame_id != config_.world_frame) {
    reject("hypotheses refused: they map into frame '" + msg->header.frame_id +
           "', not the world frame '" + config_.world_frame + "'");
    return;
  }
  std::vector<Hypothesis> hs;
  for (const auto& m : msg->hypotheses) {
    Hypothesis h;
    h.id = static_cast<int>(m.id);
    h.T_world_sketch = Sim2(m.yaw, m.scale, Eigen::Vector2d(m.tx, m.ty), m.reflected);
    h.T_world_sketch.stretch = std::exp(m.log_stretch);
    h.T_world_sketch.stretch_axis_rad = m.stretch_axis;
    h.confidence = m.confidence;
    if (const auto why = hypothesisDefect(h))
      reject("hypothesis " + std::to_string(h.id) + " refused: " + *why);
    hs.push_back(h);
  }
  manager_->setHypotheses(std::move(hs));
}

void PriorGuidedPlannerNode::onUnreachableGoal(const geometry_msgs::PointStamped::ConstPtr& msg) {
  if (refusedFrame(msg->header, "unreachable goal")) return;
  const Eigen::Vector3d goal(msg->point.x, msg->point.y, msg->point.z);
  if (!goal.allFinite()) {
    reject("unreachable goal refused: not finite");
    return;
  }
  // An older goal than the current one says nothing about the current one (kNotCurrent).
  const GoalRefusal r = manager_->reportGoalUnreachable(goal, ros::Time::now().toSec());
  if (r != GoalRefusal::kNotCurrent)
    ROS_INFO("prior_guided_planner: the local planner gave up on (%.2f, %.2f, %.2f): %s", goal.x(),
             goal.y(), goal.z(), toString(r));
}

void PriorGuidedPlannerNode::onTimer(const ros::TimerEvent&) {
  const ros::Time now = ros::Time::now();
  if (robot_ && last_odom_stamp_ && (now - *last_odom_stamp_).toSec() > config_.odom_timeout_s) {
    reject("odometry is stale (older than odom_timeout_s = " +
           std::to_string(config_.odom_timeout_s) + " s): not planning");
  } else if (robot_) {
    const ExplorationTarget& t = manager_->update(now.toSec(), *robot_);
    if (t.active_hypothesis_id) last_active_hypothesis_id_ = t.active_hypothesis_id;
    if (t.message != last_logged_) {
      if (t.message.find("refused") != std::string::npos ||
          t.message.find("dropped") != std::string::npos)
        ROS_WARN("prior_guided_planner: %s", t.message.c_str());
      else
        ROS_INFO("prior_guided_planner: [%s] %s", toString(t.state), t.message.c_str());
      last_logged_ = t.message;
    }
    std_msgs::Header header;
    header.stamp = now;
    header.frame_id = config_.world_frame;
    if (t.has_goal) {
      geometry_msgs::PoseStamped goal;
      goal.header = header;
      goal.pose.position = toPointMsg(t.goal_world_m);
      goal.pose.orientation.z = std::sin(0.5 * t.goal_yaw_rad);
      goal.pose.orientation.w = std::cos(0.5 * t.goal_yaw_rad);
      target_pub_.publish(goal);
      geometry_msgs::PointStamped look;
      look.header = header;
      look.point = toPointMsg(t.look_at_world_m);
      look_at_pub_.publish(look);
    }
    nav_msgs::Path tour;
    tour.header = header;
    geometry_msgs::PoseStamped ps;
    ps.header = header;
    ps.pose.orientation.w = 1.0;
    ps.pose.position = toPointMsg(robot_->position_world_m);
    tour.poses.push_back(ps);
    for (const Eigen::Vector3d& p : t.tour_world_m) {
      ps.pose.position = toPointMsg(p);
      tour.poses.push_back(ps);
    }
    tour_pub_.publish(tour);
    if (t.replanned) publishGuidepoints(now);
    if (t.state == ExplorationState::kFinished && !saved_at_finish_) {
      saved_at_finish_ = true;
      saveMap("exploration finished");
    }
    if (markers_pub_.getNumSubscribers() > 0)
      markers_pub_.publish(plannerMarkers(*manager_, *robot_, header, config_.markers));
  }
  publishStatus(now);
}

bool PriorGuidedPlannerNode::saveMap(const std::string& why, std::string* message) {
  std::string said;
  bool ok = false;
  if (!mission_map_) {
    said = "no mission map is kept: map_output_dir is empty";
  } else {
    MapRegistration reg;
    reg.hypotheses = manager_->hypotheses();
    std::sort(reg.hypotheses.begin(), reg.hypotheses.end(),
              [](const Hypothesis& a, const Hypothesis& b) { return a.confidence > b.confidence; });
    reg.active_hypothesis_id = last_active_hypothesis_id_;
    reg.world_frame = config_.world_frame;
    reg.sketch_frame = config_.sketch_frame;
    try {
      const SavedMissionMap s =
          mission_map_->save(config_.map_output_dir, manager_->occupancy(), reg);
      said = "mission map saved (" + why + "): " + s.cloud_pcd + " (" +
             std::to_string(s.cloud_points) + " points), " + s.occupancy_bt + " (" +
             std::to_string(s.occupied_cells) + " occupied, " + std::to_string(s.free_cells) +
             " free cells), " + s.trajectory_csv + ", " + s.registration_yaml;
      ok = true;
    } catch (const std::exception& e) {
      said = "mission map NOT saved (" + why + "): " + e.what();
    }
  }
  if (ok)
    ROS_INFO("prior_guided_planner: %s", said.c_str());
  else
    ROS_ERROR("prior_guided_planner: %s", said.c_str());
  if (message) *message = said;
  return ok;
}

bool PriorGuidedPlannerNode::onSaveMap(std_srvs::Trigger::Request&,
                                       std_srvs::Trigger::Response& res) {
  res.success = saveMap("asked by service", &res.message);
  return true;
}

void PriorGuidedPlannerNode::publishStatus(const ros::Time& now) {
  using explore_from_sketch::ExplorationStatus;
  ExplorationStatus s;
  s.header.stamp = now;
  s.header.frame_id = config_.world_frame;
  const ExplorationTarget& t = manager_->target();
  switch (t.state) {
    case ExplorationState::kWaitingForData:
      s.state = ExplorationStatus::STATE_INIT;
      break;
    case ExplorationState::kExploring:
      s.state = t.mode_used == BaselineMode::kProposed || t.mode_used == BaselineMode::kGreedyPrior
                    ? ExplorationStatus::STATE_EXPLORING_PRIOR_GUIDED
                    : ExplorationStatus::STATE_EXPLORING_PRIOR_FREE;
      break;
    case ExplorationState::kFinished:
      s.state = ExplorationStatus::STATE_FINISHED;
      break;
    case ExplorationState::kStuck:
      s.state = ExplorationStatus::STATE_EMERGENCY;
      break;
  }
  const ObservationMap& obs = manager_->observationMap();
  s.coverage_estimate = obs.numSurfaceCells() > 0
                            ? static_cast<double>(obs.numWellObserved()) / obs.numSurfaceCells()
                            : 0.0;
  s.travelled_distance = travelled_m_;
  s.elapsed_time = first_odom_stamp_ ? (now - *first_odom_stamp_).toSec() : 0.0;
  s.has_active_hypothesis = t.active_hypothesis_id.has_value();
  s.active_hypothesis_id = t.active_hypothesis_id.value_or(0);
  s.remaining_viewpoints = static_cast<uint32_t>(manager_->viewpoints().size());
  status_pub_.publish(s);
}

void PriorGuidedPlannerNode::publishGuidepoints(const ros::Time& now) {
  using explore_from_sketch::Guidepoints;
  const std::optional<GuidepointPrior>& prior = manager_->prior();
  if (!prior) return;
  Guidepoints g;
  g.header.stamp = now;
  g.header.frame_id = config_.sketch_frame;
  const HypothesisAttachment* a = manager_->activeAttachment();
  for (int i = 0; i < prior->size(); ++i) {
    g.ids.push_back(prior->ids.empty() ? static_cast<uint32_t>(i) : prior->ids[i]);
    const Eigen::Vector2d& q = prior->positions_sketch_m[i];
    g.positions.push_back(toPointMsg(Eigen::Vector3d(q.x(), q.y(), 0.0)));
    uint8_t state = Guidepoints::UNEXPLORED;
    if (a && i < static_cast<int>(a->states.size())) {
      if (a->states[i] == GuidepointState::kExploring) state = Guidepoints::EXPLORING;
      if (a->states[i] == GuidepointState::kExplored) state = Guidepoints::EXPLORED;
    }
    g.states.push_back(state);
  }
  guidepoints_pub_.publish(g);
}

}  // namespace efs::planner
