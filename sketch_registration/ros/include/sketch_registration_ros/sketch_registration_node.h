// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Thin ROS wrapper around SketchRegistration: loads the prior bundle, feeds it lio_bridge's
// registration frames (robot position + local map, 0.2 Hz), publishes the hypotheses, rviz
// markers and optionally the best hypothesis' rigid part on TF (world -> sketch). Bad frames are
// reported in the hypotheses' status and the node keeps running; a missing or corrupt bundle
// stops it with a message naming the file.
#pragma once

#include <explore_from_sketch/RegistrationFrame.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <memory>
#include <string>

#include "sketch_registration/prior_inputs.h"
#include "sketch_registration/sketch_registration.h"
#include "sketch_registration_ros/registration_msgs.h"

namespace efs::registration {

struct SketchRegistrationNodeConfig {
  std::string prior_bundle_path;    ///< a .prior file (prior_map_build); the node needs one
  double boundary_spacing_m = 0.2;  ///< sketch wall points are thinned to this spacing
  bool publish_tf = false;          ///< broadcast the best hypothesis' rigid part
  MarkerConfig markers;
  SketchRegistration::Config registration;  ///< scale_guess is 1 (see prior_inputs.h)
};

/// Reads the node's private parameters (every key of config/sketch_registration.yaml); throws
/// efs::ConfigError naming the key on a bad or unknown one.
SketchRegistrationNodeConfig loadSketchRegistrationNodeConfig(const ros::NodeHandle& private_nh);

class SketchRegistrationNode {
 public:
  /// Loads the bundle (throws ConfigError if prior_bundle_path is empty, PriorMapError naming the
  /// file if it cannot be read) and runs Phase 1.
  SketchRegistrationNode(ros::NodeHandle nh, const SketchRegistrationNodeConfig& config);

 private:
  void onFrame(const explore_from_sketch::RegistrationFrame::ConstPtr& msg);
  void publish(const RegistrationResult& result, const ros::Time& stamp);
  void publishBadInput(const std::string& why, const ros::Time& stamp);

  SketchRegistrationNodeConfig config_;
  RegistrationPrior prior_;
  std::unique_ptr<SketchRegistration> registration_;
  double last_robot_z_m_ = 0.0;  ///< where the markers are drawn (the latest finite frame)
  ros::Subscriber frame_sub_;
  ros::Publisher hypotheses_pub_, markers_pub_;
  tf2_ros::TransformBroadcaster tf_;
};

}  // namespace efs::registration
