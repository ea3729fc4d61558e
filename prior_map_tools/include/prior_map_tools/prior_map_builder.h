// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The whole offline pre-processing of paper Sec. IV in one call: sketch -> traversable region ->
// skeleton -> guidepoints -> PRM -> distance matrix -> bundle. The command-line tool and the
// prior_map_server node both use it.
#pragma once

#include <string>

#include "prior_map_tools/guidepoints.h"
#include "prior_map_tools/prior_bundle.h"
#include "prior_map_tools/prm.h"
#include "prior_map_tools/skeleton_graph.h"
#include "prior_map_tools/sketch_loader.h"
#include "prior_map_tools/traversable_region.h"

namespace efs::prior_map {

struct PriorMapConfig {
  SketchLoadConfig load;
  TraversableConfig traversable;
  SkeletonConfig skeleton;
  GuidepointConfig guidepoints;
  PrmConfig prm;

  void validate() const;
};

struct PriorMapSummary {
  double region_area_m2 = 0.0;
  int components = 0;
  double skeleton_length_m = 0.0;
  int skeleton_branches = 0;
  int guidepoints = 0;
  int prm_nodes = 0;
  int prm_edges = 0;
  int unreachable_pairs = 0;
};

/// Builds the bundle from a loaded sketch.
PriorBundle buildPriorBundle(const LoadedSketch& sketch, const PriorMapConfig& config);

PriorMapSummary summarize(const PriorBundle& bundle);

/// Overlay for a person: sketch in grey, traversable region tinted, skeleton, PRM edges and
/// guidepoints with their ids. BGR image at the sketch's resolution (upscaled if small).
cv::Mat renderOverlay(const PriorBundle& bundle);

}  // namespace efs::prior_map
