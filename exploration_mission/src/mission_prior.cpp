// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/mission_prior.h"

#include "prior_map_tools/sketch_loader.h"

namespace efs::mission {

MissionPrior prepareMissionPrior(const cv::Mat& sketch_image, double scale_guess_m_per_px,
                                 prior_map::PriorMapConfig config,
                                 const std::optional<Sim2>& truth_for_drawing_frame,
                                 double drawing_m_per_px, const std::string& description) {
  config.load.scale_guess_m_per_px = scale_guess_m_per_px;
  config.validate();
  const prior_map::LoadedSketch loaded =
      prior_map::sketchFromImage(sketch_image, config.load, description);
  MissionPrior prior;
  prior.bundle = prior_map::buildPriorBundle(loaded, config);
  prior.sketch_image = sketch_image.clone();
  prior.scale_guess_m_per_px = scale_guess_m_per_px;
  prior.description = description;
  if (truth_for_drawing_frame) {
    // Both frames share the image's bottom-left corner as origin; they differ by their unit only.
    const Sim2 T_drawing_bundle(0.0, drawing_m_per_px / scale_guess_m_per_px,
                                Eigen::Vector2d::Zero());
    prior.T_world_sketch_truth = (*truth_for_drawing_frame) * T_drawing_bundle;
  }
  return prior;
}

}  // namespace efs::mission
