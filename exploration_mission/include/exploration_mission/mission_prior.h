// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The sketch a mission flies with, pre-processed as the offline tool does (paper Sec. IV), and,
// for evaluation only, the true sketch-to-world similarity of the drawing. The flight stack is
// handed the bundle alone; the truth goes to the report.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "efs_common/sim2.h"
#include "prior_map_tools/prior_bundle.h"
#include "prior_map_tools/prior_map_builder.h"

namespace efs::mission {

struct MissionPrior {
  prior_map::PriorBundle bundle;  ///< in the sketch frame at the user's scale guess
  cv::Mat sketch_image;           ///< the drawing as given (grey), for the report's pictures
  double scale_guess_m_per_px = 0.0;
  /// Maps the bundle's sketch frame into the world. Evaluation only: never given to the stack.
  std::optional<Sim2> T_world_sketch_truth;
  std::string description;  ///< e.g. "deformed sketch of simple_cave (small, seed 3)"
};

/// Pre-processes `sketch_image` with the user's `scale_guess_m_per_px` (config.load's guess is
/// replaced). `truth_for_drawing_frame` is the sidecar's T_world_sketch of the drawing, whose frame
/// has `drawing_m_per_px` metres per pixel; it is re-expressed in the bundle's frame. Throws
/// prior_map::PriorMapError for an unusable sketch.
MissionPrior prepareMissionPrior(const cv::Mat& sketch_image, double scale_guess_m_per_px,
                                 prior_map::PriorMapConfig config,
                                 const std::optional<Sim2>& truth_for_drawing_frame,
                                 double drawing_m_per_px, const std::string& description);

/// The truth of a simulated sketch beside its bundle (`BUNDLE.truth.yaml`, evaluation only):
/// a ROS-parameter YAML map `T_world_sketch: {yaw_rad, scale, tx_m, ty_m, reflected}` that a
/// rostest can <rosparam load> and registration_replay reads. Throws std::runtime_error naming
/// the file and the key.
void saveTruth(const Sim2& T_world_sketch, const std::string& path);
Sim2 loadTruth(const std::string& path);

}  // namespace efs::mission
