// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Topics of sketch_registration_node, relative to its namespace; remap them in launch files.
#pragma once

namespace efs::registration::topics {

// Input
constexpr const char* kRegistrationFrame = "registration_frame";  // RegistrationFrame (lio_bridge)
// Outputs
constexpr const char* kHypotheses = "hypotheses";         // RegistrationHypotheses, latched
constexpr const char* kMarkers = "registration_markers";  // visualization_msgs/MarkerArray, latched

}  // namespace efs::registration::topics
