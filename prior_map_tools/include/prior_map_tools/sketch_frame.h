// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The sketch's own metric frame ("sketch" in TF terms): x to the right, y up, z out of the page;
// the origin is the lower-left corner of the image, as in ROS map_server. Pixel (col, row) with
// row 0 at the top has its centre at origin + m_per_px * (col + 0.5, height - row - 0.5).
// For a drawing, m_per_px is only the user's rough scale guess: registration recovers the true
// scale as part of the sketch-to-world similarity.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace efs::prior_map {

struct SketchFrame {
  double m_per_px = 0.1;
  Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();
  int width_px = 0;
  int height_px = 0;

  Eigen::Vector2d pixelCenter(double col, double row) const {
    return origin_m + m_per_px * Eigen::Vector2d(col + 0.5, height_px - row - 0.5);
  }
  /// Continuous pixel coordinates (col, row) of a metric point; floor() gives the cell.
  Eigen::Vector2d toPixel(const Eigen::Vector2d& p_m) const {
    const Eigen::Vector2d q = (p_m - origin_m) / m_per_px;
    return {q.x(), height_px - q.y()};
  }
  bool contains(const Eigen::Vector2d& p_m) const {
    const Eigen::Vector2d px = toPixel(p_m);
    return px.x() >= 0 && px.y() >= 0 && px.x() < width_px && px.y() < height_px;
  }
  double widthM() const { return width_px * m_per_px; }
  double heightM() const { return height_px * m_per_px; }
};

}  // namespace efs::prior_map
