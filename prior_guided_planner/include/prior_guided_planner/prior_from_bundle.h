// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The planner's view of a pre-processed sketch (prior_map_tools' PriorBundle): guidepoints in
// sketch metres with their ids, and the PRM shortest-path lengths between them. Pairs the PRM
// does not connect stay kUnreachable (never a finite "large number").
#pragma once

#include "prior_guided_planner/planner_types.h"
#include "prior_map_tools/prior_bundle.h"

namespace efs::planner {

/// Throws std::invalid_argument when the bundle's distance matrix does not match its
/// guidepoints, or a guidepoint / distance is not a finite non-negative number.
GuidepointPrior guidepointPriorFromBundle(const efs::prior_map::PriorBundle& bundle);

}  // namespace efs::planner
