// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The registration's inputs taken from the prior bundle (prior_map_tools): the sketch's wall
// points and the candidate locations of Phase 1.
//
// Units: the bundle's sketch frame is in "sketch metres" = pixels x the user's scale guess
// (SketchLoadConfig::scale_guess_m_per_px, stored as SketchFrame::m_per_px). The guess is thus
// already applied, and SketchRegistrationConfig::scale_guess (world metres per sketch metre) is
// 1.0 when the registration runs on these points; Sim2::scale of a hypothesis is then
// true metres-per-pixel / guessed metres-per-pixel. This is the frame of the sketch sidecar
// (marsim_worlds/world_sketch.h) when the guess equals the sidecar's metres_per_pixel.
#pragma once

#include "prior_map_tools/prior_bundle.h"
#include "sketch_registration/types.h"

namespace efs::registration {

struct RegistrationPrior {
  Points2d boundary_sketch_m;    ///< wall pixel centres, about boundary_spacing_m apart
  Points2d candidates_sketch_m;  ///< d_gap grid points inside the traversable region
};

/// Wall/boundary points (bundle.wallPoints() thinned so that kept points are at least
/// `boundary_spacing_m` apart and every wall pixel has one within that distance) and candidate
/// locations on a `d_gap_m` grid over the bundle's traversable region, all in sketch metres. The
/// grid is anchored half a gap inside the image's lower-left corner. Throws efs::ConfigError for a
/// non-positive or non-finite spacing; an empty bundle gives empty point sets (the registration
/// then reports kNoCandidates).
RegistrationPrior registrationPriorFromBundle(const efs::prior_map::PriorBundle& bundle,
                                              double d_gap_m, double boundary_spacing_m = 0.2);

}  // namespace efs::registration
