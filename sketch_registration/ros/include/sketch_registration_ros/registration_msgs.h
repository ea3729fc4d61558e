// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Registration results -> ROS messages: the hypotheses with their status, and rviz markers (the
// sketch boundary mapped into the world by each hypothesis, coloured by confidence; the last
// frame's candidate locations).
#pragma once

#include <explore_from_sketch/RegistrationHypotheses.h>
#include <visualization_msgs/MarkerArray.h>

#include <cstdint>
#include <string>

#include "sketch_registration/sketch_registration.h"

namespace efs::registration {

/// The message's status constant for a core status. The message has no constant for an odometry
/// jump (reported as STATUS_BAD_INPUT) or a mirrored sketch (STATUS_NO_CONSISTENT_TRIPLET: no
/// proper transform fits); status_text always starts with the core status name.
uint8_t toStatusConstant(RegistrationStatus status);

explore_from_sketch::RegistrationHypotheses toHypothesesMsg(const RegistrationResult& result,
                                                            const std_msgs::Header& header);

struct MarkerConfig {
  std::string world_frame = "world";
  std::string sketch_frame = "sketch";
  /// The sketch is drawn this far above the robot's height at the latest frame: in the passage
  /// being flown, where a person looking at the map expects it (a drawing at z = 0 under a
  /// cave 10 m up is seen displaced in any oblique view).
  double height_above_robot_m = 0.0;
  int max_boundary_points = 4000;  ///< per hypothesis (evenly thinned)
  double point_size_m = 0.15;
  double candidate_size_m = 0.6;
};

/// A DELETEALL followed by: per hypothesis (ns "sketch_boundary", id = hypothesis id) the
/// boundary mapped by its transform, red (confidence 0) to green (1); the best hypothesis'
/// label (ns "best_hypothesis"); the last frame's candidates (ns "candidates"), mapped by the
/// best hypothesis into the world, or in the sketch frame while there is none. `robot_z_m`: the
/// robot's height at the latest frame.
visualization_msgs::MarkerArray toMarkers(const RegistrationResult& result,
                                          const Points2d& boundary_sketch_m, double robot_z_m,
                                          const MarkerConfig& config, const ros::Time& stamp);

}  // namespace efs::registration
