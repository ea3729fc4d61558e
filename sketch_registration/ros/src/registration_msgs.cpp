// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration_ros/registration_msgs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace efs::registration {

using explore_from_sketch::RegistrationHypotheses;

uint8_t toStatusConstant(RegistrationStatus status) {
  switch (status) {
    case RegistrationStatus::kOk:
      return RegistrationHypotheses::STATUS_OK;
    case RegistrationStatus::kTooFewFrames:
      return RegistrationHypotheses::STATUS_TOO_FEW_FRAMES;
    case RegistrationStatus::kNoConsistentTriplet:
    case RegistrationStatus::kMirroredSketch:
      return RegistrationHypotheses::STATUS_NO_CONSISTENT_TRIPLET;
    case RegistrationStatus::kAllRejectedByFitness:
      return RegistrationHypotheses::STATUS_ALL_REJECTED_BY_FITNESS;
    case RegistrationStatus::kNoCandidates:
      return RegistrationHypotheses::STATUS_NO_CANDIDATES;
    case RegistrationStatus::kAwaitingConfirmation:
      return RegistrationHypotheses::STATUS_AWAITING_CONFIRMATION;
    case RegistrationStatus::kBadInput:
    case RegistrationStatus::kOdometryJump:
      return RegistrationHypotheses::STATUS_BAD_INPUT;
  }
  return RegistrationHypotheses::STATUS_BAD_INPUT;
}

RegistrationHypotheses toHypothesesMsg(const RegistrationResult& result,
                                       const std_msgs::Header& header) {
  RegistrationHypotheses msg;
  msg.header = header;
  msg.status = toStatusConstant(result.status);
  msg.status_text = std::string(toString(result.status)) + ": " + result.message;
  for (const Hypothesis& h : result.hypotheses) {
    explore_from_sketch::RegistrationHypothesis m;
    m.id = static_cast<uint32_t>(h.id);
    m.yaw = h.T_world_sketch.yaw_rad;
    m.scale = h.T_world_sketch.scale;
    m.tx = h.T_world_sketch.t_m.x();
    m.ty = h.T_world_sketch.t_m.y();
    m.reflected = h.T_world_sketch.reflected;
    m.log_stretch = std::log(h.T_world_sketch.stretch);
    m.stretch_axis = h.T_world_sketch.stretch_axis_rad;
    m.fitness = h.fitness_m;
    m.confidence = h.confidence;
    msg.hypotheses.push_back(m);
  }
  return msg;
}

namespace {

std_msgs::ColorRGBA confidenceColour(double confidence) {
  const double c = std::clamp(confidence, 0.0, 1.0);
  std_msgs::ColorRGBA colour;
  colour.r = static_cast<float>(1.0 - c);
  colour.g = static_cast<float>(c);
  colour.b = 0.1f;
  colour.a = static_cast<float>(0.35 + 0.65 * c);
  return colour;
}

geometry_msgs::Point point(const Eigen::Vector2d& p, double z) {
  geometry_msgs::Point out;
  out.x = p.x();
  out.y = p.y();
  out.z = z;
  return out;
}

visualization_msgs::Marker baseMarker(const std::string& frame, const std::string& ns, int id,
                                      int type, const ros::Time& stamp) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  return m;
}

}  // namespace

visualization_msgs::MarkerArray toMarkers(const RegistrationResult& result,
                                          const Points2d& boundary_sketch_m, double robot_z_m,
                                          const MarkerConfig& config, const ros::Time& stamp) {
  const double z_m = robot_z_m + config.height_above_robot_m;
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker clear;
  clear.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(clear);

  const size_t stride = std::max<size_t>(
      1, boundary_sketch_m.size() / static_cast<size_t>(std::max(1, config.max_boundary_points)));
  for (const Hypothesis& h : result.hypotheses) {
    auto m = baseMarker(config.world_frame, "sketch_boundary", h.id,
                        visualization_msgs::Marker::POINTS, stamp);
    m.scale.x = m.scale.y = config.point_size_m;
    m.color = confidenceColour(h.confidence);
    for (size_t i = 0; i < boundary_sketch_m.size(); i += stride) {
      m.points.push_back(point(h.T_world_sketch.apply(boundary_sketch_m[i]), z_m));
    }
    out.markers.push_back(m);
  }
  const std::vector<Candidate>& candidates = result.last_frame.candidates;
  const Hypothesis* best = result.hypotheses.empty() ? nullptr : &result.hypotheses.front();
  if (best) {
    auto label = baseMarker(config.world_frame, "best_hypothesis", 0,
                            visualization_msgs::Marker::TEXT_VIEW_FACING, stamp);
    char text[160];
    std::snprintf(text, sizeof(text), "hypothesis %d: confidence %.2f, F %.2f m, scale %.3f",
                  best->id, best->confidence, best->fitness_m, best->T_world_sketch.scale);
    label.text = text;
    if (!best->T_world_sketch.isSimilarity()) {
      std::snprintf(text, sizeof(text), ", stretch %.3f", best->T_world_sketch.stretch);
      label.text += text;
    }
    label.pose.position = point(result.last_frame.robot_world_m, z_m + 2.0);
    label.scale.z = 1.0;
    label.color = confidenceColour(best->confidence);
    label.color.a = 1.0f;
    out.markers.push_back(label);
  }
  if (!candidates.empty()) {
    auto m = baseMarker(best ? config.world_frame : config.sketch_frame, "candidates", 0,
                        visualization_msgs::Marker::SPHERE_LIST, stamp);
    m.scale.x = m.scale.y = m.scale.z = config.candidate_size_m;
    m.color.r = 0.2f;
    m.color.g = 0.4f;
    m.color.b = 1.0f;
    m.color.a = 0.8f;
    for (const Candidate& c : candidates) {
      m.points.push_back(point(best ? best->T_world_sketch.apply(c.c_sketch) : c.c_sketch, z_m));
    }
    out.markers.push_back(m);
  }
  return out;
}

}  // namespace efs::registration
