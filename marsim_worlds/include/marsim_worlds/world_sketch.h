// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Sketches of a world as a person would draw them (paper Section VII: precise, partial, deformed
// prior maps; plus a x2-scaled one): a top-down line drawing of the walls seen in a height band,
// black ink on white paper, unaligned with the world (random rotation, offset and pixel size).
//
// What counts as a wall: a map column (x, y) is FREE if it has a free voxel in the band, SOLID
// otherwise; wall cells are solid columns next to a free one (8-neighbourhood). In a building the
// band (1.0-1.8 m) passes through door openings and over parked cars, so doors are gaps and cars
// are not drawn; in a cave the band is the whole height, so the drawing is the passage outline.
//
// Sketch metric frame and the sidecar (the convention every module uses):
//   - the image is width_px x height_px; pixel (u, v) is column u (left to right) and row v (top to
//     bottom, as OpenCV indexes it);
//   - the sketch's metric frame has x to the right and y up, its origin at the bottom-left CORNER
//     of the image, and unit `metres_per_pixel` (the sidecar's stated drawing scale), so the
//     centre of pixel (u, v) is p_sketch = ((u + 0.5) * mpp, (height_px - v - 0.5) * mpp);
//   - T_world_sketch (efs::Sim2) maps that frame into the world: p_world_xy = s R p_sketch + t.
//     Its scale s = true_metres_per_pixel / metres_per_pixel, where true_metres_per_pixel is the
//     world distance one pixel really spans (drawn at random in a range, per sketch).
// The sidecar (<image stem>.yaml next to the PNG) records this for EVALUATION ONLY; nothing in
// the flight stack may read it. For the deformed variant T_world_sketch is the similarity the
// drawing was made with before the non-rigid deformation (which is normalised to have no net
// rotation or scale), i.e. the best rigid-plus-scale explanation of the sketch.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "efs_common/sim2.h"
#include "marsim_worlds/voxel_world.h"

namespace efs::sim {

enum class SketchVariant { kPrecise, kPartial, kDeformed, kScaled };

std::string sketchVariantName(SketchVariant v);  // "precise", "partial", "deformed", "scaled"
SketchVariant parseSketchVariant(const std::string& name);

struct SketchConfig {
  uint64_t seed = 1;
  double metres_per_pixel = 0.1;  // the sketch frame's stated unit (written to the sidecar)
  double min_true_mpp = 0.1;      // true drawing resolution, drawn uniformly in this range,
  double max_true_mpp = 0.2;      //   raised if the image would exceed max_image_px
  int max_image_px = 12000;       // longest image side
  double line_width_px = 2.0;
  int min_margin_px = 10;  // random white border on each side
  int max_margin_px = 80;
  // partial: topological regions (geodesic balls of the free space) whose walls are left out
  int partial_regions = 2;
  double partial_region_fraction = 0.12;  // geodesic radius / largest geodesic distance
  // deformed
  double deform_amplitude_fraction = 0.02;  // smooth warp amplitude / world diagonal
  double deform_max_m = 4.0;
  double anisotropy = 0.08;          // x/y scale differ by up to +-this (area preserved)
  double jitter_px = 0.7;            // hand tremor amplitude
  double thickness_variation = 0.5;  // line width varies by up to +-this fraction
  double scaled_factor = 2.0;        // the scaled variant is drawn this much larger

  void validate() const;
};

/// A wall point of the world and where the drawing put it, before the hand's tremor (sketch
/// metric frame). EVALUATION ONLY, like the sidecar. For the deformed variant the pairs carry the
/// warp that T_world_sketch (the best single similarity over the whole drawing) leaves out, so an
/// evaluation can fit the similarity that holds over the part of the world seen so far.
struct DrawnWallPoint {
  Eigen::Vector2d world_m;
  Eigen::Vector2d sketch_m;
};

struct Sketch {
  cv::Mat image;  // CV_8UC1: 0 = ink, 255 = paper
  SketchVariant variant = SketchVariant::kPrecise;
  std::string world_name;
  uint64_t seed = 0;
  double metres_per_pixel = 0.1;
  Sim2 T_world_sketch;
  SketchBand band;
  std::vector<DrawnWallPoint> drawn_walls;  ///< the walls drawn (partial: those kept)

  double trueMetresPerPixel() const { return T_world_sketch.scale * metres_per_pixel; }
  /// Centre of pixel (u, v) in the sketch metric frame.
  Eigen::Vector2d pixelToSketch(const Eigen::Vector2d& uv) const;
  /// Continuous pixel coordinates (u, v) of a point in the sketch metric frame.
  Eigen::Vector2d sketchToPixel(const Eigen::Vector2d& p_sketch) const;
  /// Where a world point falls in the image (through the sidecar transform).
  Eigen::Vector2d worldToPixel(const Eigen::Vector2d& p_world_xy) const {
    return sketchToPixel(T_world_sketch.inverse().apply(p_world_xy));
  }
  bool inkAt(const Eigen::Vector2d& uv) const;
};

/// World xy centres of the wall cells of `world` in `band` (see the file comment).
std::vector<Eigen::Vector2d> wallPoints(const VoxelWorld& world, const SketchBand& band);

/// Draws one variant; deterministic in (world, variant, config.seed).
Sketch drawSketch(const VoxelWorld& world, SketchVariant variant, const SketchConfig& config);

/// Writes `png_path` and its sidecar (same stem, .yaml); returns the sidecar path.
std::string saveSketch(const Sketch& sketch, const std::string& png_path);
/// Reads a PNG and its sidecar; throws std::runtime_error naming the file and the key.
Sketch loadSketch(const std::string& png_path);
/// The sidecar path of a sketch PNG.
std::string sidecarPath(const std::string& png_path);

/// Top-down picture of a world for people: free columns in the band white, walls black, solid
/// grey, start poses as red arrows. CV_8UC3, north up, `metres_per_pixel` per pixel.
cv::Mat renderTopDown(const VoxelWorld& world, double metres_per_pixel);
/// Where a world point falls in renderTopDown(world, metres_per_pixel) (sub-pixel).
cv::Point2d topDownPixel(const VoxelWorld& world, double metres_per_pixel,
                         const Eigen::Vector2d& p_world_xy);

}  // namespace efs::sim
