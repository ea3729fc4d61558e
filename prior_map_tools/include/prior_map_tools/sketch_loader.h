// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Imports a prior map: a drawing (PNG, JPG, PGM, ...: grey, colour or with alpha) or a ROS
// map_server occupancy grid (YAML + image, resolution and origin taken from the YAML).
#pragma once

#include <opencv2/core.hpp>
#include <string>

#include "prior_map_tools/sketch_frame.h"

namespace efs::prior_map {

enum class SketchKind {
  kAuto,         ///< YAML -> occupancy grid; image with many mid-grey pixels -> grid; else drawing
  kLineDrawing,  ///< dark lines are walls; everything else is free paper
  kOccupancyGrid,  ///< dark = occupied, light = free, mid grey = unknown (never traversable)
};

const char* toString(SketchKind kind);

struct SketchLoadConfig {
  SketchKind kind = SketchKind::kAuto;
  /// The user's rough guess of metres per pixel (drawings). Must be finite and > 0. Ignored for
  /// map_server YAML files, which state their resolution.
  double scale_guess_m_per_px = 0.1;
  /// Luminance below which a drawing pixel is a wall (0..255).
  int wall_threshold = 128;
  /// Images larger than this many pixels are refused (memory: a few bytes per pixel per layer).
  long max_image_pixels = 64L * 1000 * 1000;
  /// Occupancy-grid thresholds on occupancy probability (map_server semantics).
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  /// Fraction of mid-grey pixels above which kAuto treats a plain image as an occupancy grid.
  double auto_grid_unknown_fraction = 0.05;

  void validate() const;
};

struct LoadedSketch {
  std::string source_path;
  SketchKind kind = SketchKind::kLineDrawing;
  SketchFrame frame;
  cv::Mat1b wall_mask;     ///< 255 where the sketch shows a wall / obstacle
  cv::Mat1b unknown_mask;  ///< 255 where the sketch says nothing (grids only; zeros for drawings)
};

/// Loads a sketch. Throws PriorMapError naming the file and the problem: missing file, not an
/// image, zero size, too large, malformed YAML, bad scale guess.
LoadedSketch loadSketch(const std::string& path, const SketchLoadConfig& config);

/// Builds a LoadedSketch from an image already in memory (grey, BGR or BGRA, 8-bit).
LoadedSketch sketchFromImage(const cv::Mat& image, const SketchLoadConfig& config,
                             const std::string& name = "<memory>");

}  // namespace efs::prior_map
