// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/planner_types.h"

#include <cmath>
#include <stdexcept>

#include "efs_common/config_check.h"
#include "prior_guided_planner/baseline_mode.h"

namespace efs::planner {

std::optional<std::string> hypothesisDefect(const Hypothesis& h) {
  if (!h.T_world_sketch.isFinite()) return "transform is not finite (NaN or inf)";
  if (!(h.T_world_sketch.scale > 0.0))
    return "scale " + std::to_string(h.T_world_sketch.scale) + " is not positive";
  if (!(h.T_world_sketch.stretch >= 1.0))
    return "stretch " + std::to_string(h.T_world_sketch.stretch) +
           " is below 1 (a negative log_stretch)";
  if (!std::isfinite(h.confidence) || h.confidence < 0.0)
    return "confidence " + std::to_string(h.confidence) + " is not a finite number >= 0";
  return std::nullopt;
}

void GuidepointPrior::validate() const {
  const int n = size();
  if (!ids.empty() && static_cast<int>(ids.size()) != n)
    throw std::invalid_argument("GuidepointPrior: " + std::to_string(ids.size()) + " ids for " +
                                std::to_string(n) + " guidepoints");
  if (prm_distance_m.size() != n)
    throw std::invalid_argument(
        "GuidepointPrior: PRM matrix is " + std::to_string(prm_distance_m.size()) + " x " +
        std::to_string(prm_distance_m.size()) + " for " + std::to_string(n) + " guidepoints");
  for (int i = 0; i < n; ++i) {
    if (!positions_sketch_m[i].allFinite())
      throw std::invalid_argument("GuidepointPrior: guidepoint " + std::to_string(i) +
                                  " has a non-finite position");
    for (int j = 0; j < n; ++j) {
      const double d = prm_distance_m(i, j);
      if (std::isnan(d) || d < 0.0)
        throw std::invalid_argument("GuidepointPrior: PRM distance (" + std::to_string(i) + ", " +
                                    std::to_string(j) + ") is NaN or negative");
    }
  }
  if (!predicted_free_sketch_m.empty() &&
      !(std::isfinite(predicted_free_cell_m) && predicted_free_cell_m > 0.0))
    throw std::invalid_argument("GuidepointPrior: predicted_free_cell_m " +
                                std::to_string(predicted_free_cell_m) + " is not positive");
  for (size_t i = 0; i < predicted_free_sketch_m.size(); ++i)
    if (!predicted_free_sketch_m[i].allFinite())
      throw std::invalid_argument("GuidepointPrior: predicted free sample " + std::to_string(i) +
                                  " is not finite");
}

std::string toString(BaselineMode mode) {
  switch (mode) {
    case BaselineMode::kProposed:
      return "proposed";
    case BaselineMode::kPriorFree:
      return "prior_free";
    case BaselineMode::kGreedyPrior:
      return "greedy_prior";
    case BaselineMode::kNearestFrontier:
      return "nearest_frontier";
  }
  return "unknown";
}

BaselineMode parseBaselineMode(const std::string& name, const std::string& key) {
  for (BaselineMode m : {BaselineMode::kProposed, BaselineMode::kPriorFree,
                         BaselineMode::kGreedyPrior, BaselineMode::kNearestFrontier})
    if (toString(m) == name) return m;
  throw ConfigError("parameter '" + key + "' = '" + name +
                    "' is not one of proposed, prior_free, greedy_prior, nearest_frontier");
}

}  // namespace efs::planner
