// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/prior_inputs.h"

#include <cmath>
#include <unordered_map>

#include "efs_common/config_check.h"
#include "efs_common/voxel_key.h"
#include "sketch_registration/candidate_database.h"

namespace efs::registration {

namespace {

/// Greedy Poisson-disk thinning: a point is kept unless a kept point lies closer than
/// `spacing_m`. Every input point thus has a kept point within `spacing_m`, and a stroke a few
/// pixels wide gives about one point per `spacing_m` of its length.
Points2d thinPoints(const Points2d& points, double spacing_m) {
  std::unordered_map<long long, std::vector<size_t>> grid;  // cell -> indices into `out`
  const auto cellOf = [&](double v) { return static_cast<long long>(std::floor(v / spacing_m)); };
  Points2d out;
  for (const Eigen::Vector2d& p : points) {
    if (!p.allFinite()) continue;
    const long long cx = cellOf(p.x()), cy = cellOf(p.y());
    bool covered = false;
    for (long long dy = -1; dy <= 1 && !covered; ++dy) {
      for (long long dx = -1; dx <= 1 && !covered; ++dx) {
        const auto it = grid.find(cellKey2d(cx + dx, cy + dy));
        if (it == grid.end()) continue;
        for (size_t i : it->second) {
          if ((out[i] - p).norm() < spacing_m) {
            covered = true;
            break;
          }
        }
      }
    }
    if (covered) continue;
    grid[cellKey2d(cx, cy)].push_back(out.size());
    out.push_back(p);
  }
  return out;
}

}  // namespace

RegistrationPrior registrationPriorFromBundle(const efs::prior_map::PriorBundle& bundle,
                                              double d_gap_m, double boundary_spacing_m) {
  requirePositive("d_gap_m", d_gap_m);
  requirePositive("boundary_spacing_m", boundary_spacing_m);
  RegistrationPrior prior;
  prior.boundary_sketch_m = thinPoints(bundle.wallPoints(), boundary_spacing_m);

  const cv::Mat1b& traversable = bundle.traversable;
  const auto& frame = bundle.frame;
  if (traversable.empty() || traversable.rows != frame.height_px ||
      traversable.cols != frame.width_px) {
    return prior;
  }
  const auto inside = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d px = frame.toPixel(p);
    const int col = static_cast<int>(std::floor(px.x()));
    const int row = static_cast<int>(std::floor(px.y()));
    if (col < 0 || row < 0 || col >= traversable.cols || row >= traversable.rows) return false;
    return traversable(row, col) != 0;
  };
  const Eigen::Vector2d min_m = frame.origin_m + Eigen::Vector2d::Constant(0.5 * d_gap_m);
  const Eigen::Vector2d max_m = frame.origin_m + Eigen::Vector2d(frame.widthM(), frame.heightM());
  prior.candidates_sketch_m = makeCandidateGrid(min_m, max_m, d_gap_m, inside);
  return prior;
}

}  // namespace efs::registration
