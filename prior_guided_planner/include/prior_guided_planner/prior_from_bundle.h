// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The planner's view of a pre-processed sketch (prior_map_tools' PriorBundle): guidepoints in
// sketch metres with their ids, and the PRM shortest-path lengths between them. Pairs the PRM
// does not connect stay kUnreachable (never a finite "large number"). The traversable region is
// sampled on a grid of about `predicted_free_spacing_m` (sketch metres) for the greedy_prior
// baseline's predicted information gain.
#pragma once

#include "prior_guided_planner/planner_types.h"
#include "prior_map_tools/prior_bundle.h"

namespace efs::planner {

/// Throws std::invalid_argument when the bundle's distance matrix does not match its
/// guidepoints, a guidepoint / distance is not a finite non-negative number, the traversable
/// image does not match the frame, or the spacing is not positive.
GuidepointPrior guidepointPriorFromBundle(const efs::prior_map::PriorBundle& bundle,
                                          double predicted_free_spacing_m = 1.0);

}  // namespace efs::planner
