// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Exploration strategies the planner can run: the paper's method and the baselines it is
// compared against (issue 5). Selected by a parameter; parsing names the allowed values.
#pragma once

#include <string>

namespace efs::planner {

enum class BaselineMode {
  kProposed,         ///< prior-guided hierarchical planning (paper Sec. VI)
  kPriorFree,        ///< ATSP over all viewpoints from the robot (EPIC-like)
  kGreedyPrior,      ///< greedy frontier utility from information predicted on the sketch
  kNearestFrontier,  ///< classic frontier exploration without the prior (FUEL-like)
};

/// "proposed", "prior_free", "greedy_prior", "nearest_frontier".
std::string toString(BaselineMode mode);
/// Throws efs::ConfigError naming `key` and the allowed values on an unknown name.
BaselineMode parseBaselineMode(const std::string& name, const std::string& key = "mode");

}  // namespace efs::planner
