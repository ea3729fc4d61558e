// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration_ros/sketch_registration_node.h"

#include <geometry_msgs/TransformStamped.h>

#include <cmath>

#include "efs_common/config_check.h"
#include "efs_common/resource_usage.h"
#include "efs_common_ros/cloud_conversions.h"
#include "efs_common_ros/param_reader.h"
#include "prior_map_tools/prior_bundle.h"
#include "sketch_registration_ros/topics.h"

namespace efs::registration {

SketchRegistrationNodeConfig loadSketchRegistrationNodeConfig(const ros::NodeHandle& private_nh) {
  ros_common::ParamReader p(private_nh);
  SketchRegistrationNodeConfig c;
  SketchRegistration::Config& r = c.registration;
  p.get("prior_bundle_path", c.prior_bundle_path);
  p.get("world_frame", c.markers.world_frame);
  p.get("sketch_frame", c.markers.sketch_frame);
  p.get("publish_tf", c.publish_tf);
  p.get("marker_height_above_robot_m", c.markers.height_above_robot_m);
  p.get("marker_max_boundary_points", c.markers.max_boundary_points);
  p.get("boundary_spacing_m", c.boundary_spacing_m);
  p.get("d_gap_m", r.d_gap_m);
  p.get("scale_tolerance_factor", r.scale_tolerance_factor);
  std::string reflection = "detect";
  p.get("reflection", reflection);
  if (reflection == "ignore") {
    r.reflection = ReflectionMode::kIgnore;
  } else if (reflection == "detect") {
    r.reflection = ReflectionMode::kDetect;
  } else if (reflection == "register") {
    r.reflection = ReflectionMode::kRegister;
  } else {
    throw ConfigError("parameter 'reflection' = '" + reflection +
                      "' must be ignore, detect or register");
  }
  p.get("num_bins", r.descriptor.num_bins);
  p.get("num_fft", r.descriptor.num_fft);
  p.get("max_range_m", r.descriptor.max_range_m);
  p.get("eta", r.retrieval.eta);
  p.get("alpha_cos", r.retrieval.weights.alpha_cos);
  p.get("alpha_fft", r.retrieval.weights.alpha_fft);
  p.get("alpha_cv", r.retrieval.weights.alpha_cv);
  p.get("downsample_radius_m", r.retrieval.downsample_radius_m);
  p.get("max_candidates_per_frame", r.retrieval.max_candidates_per_frame);
  p.get("min_ranked_candidates", r.retrieval.min_ranked_candidates);
  p.get("match_radius_m", r.verifier.match_radius_m);
  p.get("candidate_position_error_m", r.verifier.candidate_position_error_m);
  p.get("lambda_t", r.verifier.lambda.lambda_t);
  p.get("lambda_r", r.verifier.lambda.lambda_r);
  p.get("lambda_s", r.verifier.lambda.lambda_s);
  p.get("dbscan_eps", r.verifier.dbscan_eps);
  p.get("n_f", r.verifier.n_f);
  p.get("fitness_threshold_m", r.fitness_threshold_m);
  p.get("confidence_tau", r.confidence_tau);
  p.get("kept_fitness_threshold_m", r.kept_fitness_threshold_m);
  p.get("min_inlier_ratio", r.icp.min_inlier_ratio);
  p.get("kept_min_inlier_ratio", r.kept_min_inlier_ratio);
  p.get("forward_inlier_slack", r.icp.forward_inlier_slack);
  p.get("slack_min_reverse_ratio", r.icp.slack_min_reverse_ratio);
  p.get("max_stretch", r.icp.max_stretch);
  p.get("stretch_min_fitness_gain", r.stretch_min_fitness_gain);
  p.get("min_inside_ratio", r.icp.min_inside_ratio);
  p.get("kept_min_inside_ratio", r.kept_min_inside_ratio);
  p.get("kept_drawing_reach_m", r.kept_drawing_reach_m);
  p.get("kept_drawing_reach_min_age_frames", r.kept_drawing_reach_min_age_frames);
  p.get("confirm_frames", r.confirm_frames);
  p.get("dormant_frames", r.dormant_frames);
  p.get("settled_coverage", r.settled_coverage);
  p.get("coverage_weight_m", r.coverage_weight_m);
  p.get("screen_points", r.screen_points);
  p.get("screen_iterations", r.screen_iterations);
  p.get("mirror_dominance_coverage", r.mirror_dominance_coverage);
  p.get("empty_observed_bins_unknown", r.descriptor.empty_observed_bins_unknown);
  p.get("clip_to_range", r.descriptor.clip_to_range);
  p.get("mirror_score_margin", r.descriptor.mirror_score_margin);
  p.get("sketch_point_radius_m", r.sketch_point_radius_m);
  p.get("scale_levels", r.scale_levels);
  p.get("wall_columns", r.observation.wall_columns);
  p.get("slice_min_dz_m", r.observation.slice_min_dz_m);
  p.get("slice_max_dz_m", r.observation.slice_max_dz_m);
  p.get("column_cell_m", r.observation.column_cell_m);
  p.get("wall_min_height_m", r.observation.wall_min_height_m);
  p.get("wall_max_gap_m", r.observation.wall_max_gap_m);
  p.get("wall_top_clear_m", r.observation.wall_top_clear_m);
  p.get("wall_continuation_m", r.observation.wall_continuation_m);
  p.get("max_speed_mps", r.max_speed_mps);
  p.get("max_hypotheses", r.max_hypotheses);
  p.get("history_enabled", r.history.enabled);
  p.get("history_cell_m", r.history.cell_m);
  p.get("history_forget_radius_m", r.history.forget_radius_m);
  p.get("history_radius_m", r.history.radius_m);
  p.get("history_max_points", r.history.max_points);
  p.get("history_min_points", r.history.min_points);
  p.get("history_inlier_slack", r.history_inlier_slack);
  p.get("history_min_inlier_ratio", r.history_min_inlier_ratio);
  p.get("history_kept_min_inlier_ratio", r.history_kept_min_inlier_ratio);
  p.get("history_inlier_margin", r.history_inlier_margin);
  p.rejectUnknown();

  requireThat(!c.markers.world_frame.empty(), "world_frame", "must not be empty");
  requireThat(!c.markers.sketch_frame.empty(), "sketch_frame", "must not be empty");
  requireInRange("marker_max_boundary_points", c.markers.max_boundary_points, 1, 1000000);
  requireThat(std::isfinite(c.markers.height_above_robot_m), "marker_height_above_robot_m",
              "must be finite");
  requirePositive("boundary_spacing_m", c.boundary_spacing_m);
  r.scale_guess = 1.0;  // the bundle's sketch frame already carries the user's scale guess
  r.validate();
  return c;
}

SketchRegistrationNode::SketchRegistrationNode(ros::NodeHandle nh,
                                               const SketchRegistrationNodeConfig& config)
    : config_(config) {
  // Checked here, not by the loader: the shipped YAML leaves it to the launch file.
  requireThat(!config_.prior_bundle_path.empty(), "prior_bundle_path",
              "must name a .prior file (prior_map_build)");
  const prior_map::PriorBundle bundle = prior_map::loadPriorBundle(config_.prior_bundle_path);
  prior_ =
      registrationPriorFromBundle(bundle, config_.registration.d_gap_m, config_.boundary_spacing_m);
  const Stopwatch watch;
  registration_ = std::make_unique<SketchRegistration>(
      config_.registration, prior_.boundary_sketch_m, prior_.candidates_sketch_m);
  ROS_INFO("sketch_registration: %s: %zu wall points, %zu candidates (%zu usable); Phase 1 %.2f s",
           config_.prior_bundle_path.c_str(), prior_.boundary_sketch_m.size(),
           prior_.candidates_sketch_m.size(), registration_->database().validCount(),
           watch.elapsedSeconds());
  if (registration_->database().validCount() == 0) {
    ROS_WARN(
        "sketch_registration: %s gives no usable candidate location; every frame will report "
        "no_candidates",
        config_.prior_bundle_path.c_str());
  }
  hypotheses_pub_ =
      nh.advertise<explore_from_sketch::RegistrationHypotheses>(topics::kHypotheses, 1, true);
  markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>(topics::kMarkers, 1, true);
  frame_sub_ = nh.subscribe(topics::kRegistrationFrame, 2, &SketchRegistrationNode::onFrame, this);
}

void SketchRegistrationNode::publishBadInput(const std::string& why, const ros::Time& stamp) {
  ROS_WARN("sketch_registration: %s", why.c_str());
  RegistrationResult bad = registration_->result();
  bad.status = RegistrationStatus::kBadInput;
  bad.message = why;
  publish(bad, stamp);
}

void SketchRegistrationNode::onFrame(const explore_from_sketch::RegistrationFrame::ConstPtr& msg) {
  const ros::Time stamp = msg->header.stamp;
  if (!msg->header.frame_id.empty() && msg->header.frame_id != config_.markers.world_frame) {
    publishBadInput("registration frame in '" + msg->header.frame_id + "', expected '" +
                        config_.markers.world_frame + "'; frame ignored",
                    stamp);
    return;
  }
  std::vector<Eigen::Vector3f> cloud;
  try {
    cloud = ros_common::fromPointCloud2(msg->local_map);
  } catch (const std::exception& e) {
    publishBadInput(std::string("local map unreadable: ") + e.what() + "; frame ignored", stamp);
    return;
  }
  Points3d map;
  map.reserve(cloud.size());
  for (const Eigen::Vector3f& p : cloud) map.push_back(p.cast<double>());
  const Eigen::Vector3d robot(msg->robot_position.x, msg->robot_position.y, msg->robot_position.z);
  if (std::isfinite(robot.z())) last_robot_z_m_ = robot.z();
  const RegistrationResult& result = registration_->addFrame(stamp.toSec(), robot, map);
  if (result.status == RegistrationStatus::kBadInput ||
      result.status == RegistrationStatus::kOdometryJump) {
    ROS_WARN("sketch_registration: %s: %s", toString(result.status), result.message.c_str());
  } else {
    ROS_INFO("sketch_registration: %s: %s", toString(result.status), result.message.c_str());
  }
  publish(result, stamp);
}

void SketchRegistrationNode::publish(const RegistrationResult& result, const ros::Time& stamp) {
  std_msgs::Header header;
  header.stamp = stamp;
  header.frame_id = config_.markers.world_frame;
  hypotheses_pub_.publish(toHypothesesMsg(result, header));
  markers_pub_.publish(
      toMarkers(result, prior_.boundary_sketch_m, last_robot_z_m_, config_.markers, stamp));
  if (config_.publish_tf && !result.hypotheses.empty() &&
      !result.hypotheses.front().T_world_sketch.reflected) {
    // TF carries neither scale nor reflection: only the best hypothesis' rotation and translation.
    const Sim2& T = result.hypotheses.front().T_world_sketch;
    geometry_msgs::TransformStamped t;
    t.header = header;
    t.child_frame_id = config_.markers.sketch_frame;
    t.transform.translation.x = T.t_m.x();
    t.transform.translation.y = T.t_m.y();
    t.transform.rotation.z = std::sin(0.5 * T.yaw_rad);
    t.transform.rotation.w = std::cos(0.5 * T.yaw_rad);
    tf_.sendTransform(t);
  }
}

}  // namespace efs::registration
