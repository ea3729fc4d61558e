// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Which part of the sketch the robot can be in (paper Sec. IV-A). For a line drawing this is the
// building's interior: free paper enclosed by the outer walls, even where the outer wall is drawn
// with gaps (doors to the outside, sloppy strokes). The outside of the building is never
// traversable. For an occupancy grid it is the known-free space.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "prior_map_tools/sketch_loader.h"

namespace efs::prior_map {

struct TraversableConfig {
  /// Clearance kept from a drawn wall [m, in the sketch's guessed scale]. Small on purpose: a
  /// gap in a sketch means a passage, and the scale guess may be half the truth, which halves
  /// every door; the planner checks real clearance against the LiDAR map.
  double robot_radius_m = 0.15;
  /// Largest gap in the outer wall that is still a wall (a door to the outside) [m]. The gap
  /// closing radius is chosen automatically up to this bound, so a wrong scale guess (x2) is
  /// tolerated.
  double max_outer_gap_m = 4.0;
  /// Components smaller than this are dropped (closets without doors, specks) [m^2].
  double min_region_area_m2 = 2.0;
  /// An enclosed area whose bounding box spans less than this fraction of the ink's (diagonals)
  /// is a closet or a service core inside an outline the drawing left open (a partial sketch),
  /// not the building: the footprint is then found as open_outline_gap_m says. A building's or a
  /// cave's own outline spans its strokes.
  double min_enclosed_span_fraction = 0.5;
  /// Where the outline is open, the inside is what the strokes enclose once gaps up to this
  /// wide are closed (the drifts between a mine's pillars, a wing drawn without its outer wall),
  /// within their convex hull; 0: the whole convex hull [m, in the sketch's guessed scale].
  /// Off by default: the hull spans the empty page between a mine drawing's arms, but at 40 m
  /// the mine's partial flight ended later (time limit, against 1892.5 s), and so did the paper
  /// simple cave's (462.5 against 427.7 s: the drawing cut in two where a tunnel was left out).
  double open_outline_gap_m = 0.0;
  /// The inside of a closed loop that no stroke joins to the outline (a pillar drawn as a
  /// square, a service core) is solid, not traversable: rooms and corridors border the outline
  /// or walls joined to it. false: every enclosed pixel counts (min_region_area_m2 alone drops
  /// the small ones).
  bool drop_island_interiors = true;

  void validate() const;
};

struct TraversableRegion {
  cv::Mat1b mask;        ///< 255 = traversable (after clearance), 0 = not
  cv::Mat1b footprint;   ///< 255 = inside the building outline (drawings); = free for grids
  cv::Mat1i components;  ///< component label per pixel, 0 = none, 1..n
  std::vector<double> component_area_m2;  ///< index i holds label i + 1, largest first
  int outer_gap_closing_px = 0;           ///< radius used to seal the outer wall (drawings)
  /// The drawing's outline encloses no usable region, or only one spanning a small part of the
  /// strokes (a partial sketch): the footprint is what the strokes close (open_outline_gap_m).
  bool outer_outline_open = false;
  double area_m2 = 0.0;

  int numComponents() const { return static_cast<int>(component_area_m2.size()); }
};

/// Throws PriorMapError if nothing traversable remains (all black, all white, no interior, or a
/// region too small for the robot), naming the sketch and the reason.
TraversableRegion extractTraversable(const LoadedSketch& sketch, const TraversableConfig& config);

}  // namespace efs::prior_map
