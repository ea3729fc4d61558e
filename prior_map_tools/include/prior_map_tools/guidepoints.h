// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Prior guidepoints (paper Sec. IV-B): sparse points along the skeleton that carry the sketch's
// topology to the planner. Every branch long enough to matter gets at least one, spaced about
// `interval_m` apart; junctions and skeleton endpoints themselves are avoided because they give
// no direction; each independent region gets one even if its skeleton is short; open areas far
// from the skeleton get some until every place is near one.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "prior_map_tools/skeleton_graph.h"
#include "prior_map_tools/sketch_frame.h"
#include "prior_map_tools/traversable_region.h"

namespace efs::prior_map {

struct GuidepointConfig {
  /// The robot's mapping range [m]; the paper samples every 2 to 4 times this.
  double mapping_range_m = 10.0;
  /// Sampling interval as a multiple of the mapping range.
  double interval_factor = 3.0;
  /// A terminal branch (dead end, room) shorter than this multiple of the mapping range is seen
  /// from its junction and gets no guidepoint of its own.
  double min_dead_end_factor = 0.5;
  /// A branch between two junctions shorter than this multiple of the mapping range is part of
  /// an intersection and gets no guidepoint of its own.
  double min_link_factor = 1.0;
  /// No skeleton pixel may be farther along the skeleton than this multiple of the interval from
  /// a guidepoint (fills corridors made of many short branches between side doors).
  double coverage_factor = 0.75;
  /// No traversable point may be farther along the region than this multiple of the interval
  /// from a guidepoint: an open hall's skeleton (its medial axis) keeps far from its sides, and
  /// the viewpoints there attached to no guidepoint. The planner tours such "isolated"
  /// viewpoints first, meant for places the sketch leaves out; in a 192 x 150 m garage with
  /// guidepoints on the skeleton alone (59) most viewpoints were isolated and the guided flight
  /// stayed in one corner for 200 s. 0 = off.
  double region_cover_factor = 0.75;

  double intervalM() const { return interval_factor * mapping_range_m; }
  void validate() const;
};

struct Guidepoint {
  uint32_t id = 0;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  ///< sketch frame
  static constexpr int kNoBranch = -1;
  int component = 0;       ///< traversable component label
  int branch = kNoBranch;  ///< skeleton branch it lies on; kNoBranch for gap fills and seeds
};

std::vector<Guidepoint> sampleGuidepoints(const SkeletonGraph& skeleton,
                                          const TraversableRegion& region, const SketchFrame& frame,
                                          const GuidepointConfig& config);

}  // namespace efs::prior_map
