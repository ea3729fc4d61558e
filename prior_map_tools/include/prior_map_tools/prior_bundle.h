// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The "prior bundle": everything the online nodes need from the sketch, computed once offline
// and stored in one versioned file so that nodes start without recomputing.
//
// File layout (little endian): magic "EFSPRIOR", uint32 format version, uint32 section count,
// then per section: 4-byte tag, uint64 payload size, payload, uint32 CRC-32 of the payload.
// Images are stored PNG-encoded (lossless). A reader refuses other versions, truncated files and
// sections whose CRC does not match, naming the file, the section and the byte offset.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "prior_map_tools/guidepoints.h"
#include "prior_map_tools/prm.h"
#include "prior_map_tools/skeleton_graph.h"
#include "prior_map_tools/sketch_loader.h"
#include "prior_map_tools/traversable_region.h"

namespace efs::prior_map {

struct PriorBundle {
  static constexpr uint32_t kFormatVersion = 1;

  std::string source_path;  ///< the sketch it was built from (informative)
  SketchKind kind = SketchKind::kLineDrawing;
  SketchFrame frame;
  cv::Mat1b wall_mask;    ///< the sketch's walls (255)
  cv::Mat1b traversable;  ///< 255 = traversable
  cv::Mat1b skeleton;     ///< 255 = skeleton pixel
  std::vector<Guidepoint> guidepoints;
  Prm prm;
  DistanceMatrix distances;
  double mapping_range_m = 0.0;  ///< the value guidepoints were sampled for

  /// Wall pixels as metric points in the sketch frame (boundary points for registration).
  std::vector<Eigen::Vector2d> wallPoints() const;
};

void savePriorBundle(const PriorBundle& bundle, const std::string& path);
/// Throws PriorMapError (wrong magic or version, truncated, corrupt section, missing section).
PriorBundle loadPriorBundle(const std::string& path);

bool operator==(const PriorBundle& a, const PriorBundle& b);

}  // namespace efs::prior_map
