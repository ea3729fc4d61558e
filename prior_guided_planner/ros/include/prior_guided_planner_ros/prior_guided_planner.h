// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// prior_guided_planner_node: a thin ROS wrapper of efs::planner::ExplorationManager. Scans
// (world frame, from lio_bridge) and odometry feed the maps; registration hypotheses and the
// prior bundle (a file; empty path = prior-free) feed the planner; a timer plans with ROS time
// injected as seconds and publishes the target, the local tour, the status, the guidepoint
// states and rviz markers. Bad input (malformed or non-finite clouds, odometry going back in
// time or not finite, hypotheses with NaN or non-positive scale, clouds or hypotheses in another
// frame) is refused or cleaned with a logged reason; the node keeps running.
// With map_output_dir set, the node keeps what the mission leaves behind (planner::MissionMap:
// dense cloud, OctoMap of its occupancy, track, registration) and writes it there when the
// exploration finishes, when asked (service save_map) and when the node shuts down.
#pragma once

#include <explore_from_sketch/RegistrationHypotheses.h>
#include <geometry_msgs/PointStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Trigger.h>

#include <optional>
#include <string>

#include "efs_common/position_history.h"
#include "prior_guided_planner/exploration_manager.h"
#include "prior_guided_planner/mission_map.h"
#include "prior_guided_planner_ros/planner_markers.h"

namespace efs::planner {

struct PriorGuidedPlannerNodeConfig {
  std::string world_frame = "world";
  std::string sketch_frame = "sketch";
  std::string prior_bundle_path;  ///< empty: no sketch, prior-free
  double predicted_free_spacing_m = 1.0;
  /// Updates a second. At the LiDAR's frame rate, as the in-process mission updates after every
  /// scan: at 2 Hz the vehicle flew 1.5-2 m toward targets already gone (README, "How often the
  /// planner updates").
  double plan_rate_hz = 10.0;
  double odom_timeout_s = 1.0;
  PositionHistoryConfig scan_origin;  ///< where the sensor was at each scan's stamp
  PlannerMarkerOptions markers;
  ExplorationManagerConfig exploration;
  std::string map_output_dir;  ///< empty: no map is kept or saved
  MissionMapConfig mission_map;
};

/// Reads and validates the private parameters (every key of config/prior_guided_planner.yaml);
/// throws efs::ConfigError naming the key.
PriorGuidedPlannerNodeConfig loadPriorGuidedPlannerConfig(const ros::NodeHandle& private_nh);

class PriorGuidedPlannerNode {
 public:
  /// Throws when the prior bundle cannot be loaded (the message names the file and the defect).
  PriorGuidedPlannerNode(ros::NodeHandle nh, const PriorGuidedPlannerNodeConfig& config);

  /// Writes the mission map to map_output_dir (nothing without one); `why` goes into the log.
  /// Returns false, with the reason logged and in `message`, when a file cannot be written.
  bool saveMap(const std::string& why, std::string* message = nullptr);

 private:
  void onOdometry(const nav_msgs::Odometry::ConstPtr& msg);
  void onScan(const sensor_msgs::PointCloud2::ConstPtr& msg);
  void onHypotheses(const explore_from_sketch::RegistrationHypotheses::ConstPtr& msg);
  void onUnreachableGoal(const geometry_msgs::PointStamped::ConstPtr& msg);
  void onTimer(const ros::TimerEvent&);
  void publishStatus(const ros::Time& now);
  void publishGuidepoints(const ros::Time& now);
  void reject(const std::string& why);
  /// Refuses (says so, returns true) input stamped in a frame other than the world frame; an
  /// empty frame is taken as the world frame.
  bool refusedFrame(const std_msgs::Header& header, const std::string& what);
  bool onSaveMap(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);

  PriorGuidedPlannerNodeConfig config_;
  std::optional<ExplorationManager> manager_;
  std::optional<MissionMap> mission_map_;
  bool saved_at_finish_ = false;
  std::optional<int> last_active_hypothesis_id_;  ///< the last one the guidance used
  std::optional<RobotPose> robot_;
  PositionHistory positions_;  ///< scans are ray cast from here at their own stamps
  std::optional<ros::Time> last_odom_stamp_;
  std::optional<ros::Time> first_odom_stamp_;
  double travelled_m_ = 0.0;
  std::string last_logged_;
  std::string last_reject_;
  ros::WallTime last_reject_time_;

  ros::Subscriber odom_sub_, scan_sub_, hyp_sub_, unreachable_sub_;
  ros::Publisher target_pub_, look_at_pub_, tour_pub_, status_pub_, guidepoints_pub_, markers_pub_;
  ros::ServiceServer save_map_srv_;
  ros::Timer timer_;
};

}  // namespace efs::planner
