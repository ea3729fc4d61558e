// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/prior_from_bundle.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace efs::planner {

GuidepointPrior guidepointPriorFromBundle(const efs::prior_map::PriorBundle& bundle,
                                          double spacing_m) {
  if (!(std::isfinite(spacing_m) && spacing_m > 0.0))
    throw std::invalid_argument("prior bundle: predicted free spacing " +
                                std::to_string(spacing_m) + " m is not positive");
  const int n = static_cast<int>(bundle.guidepoints.size());
  if (bundle.distances.size() != n)
    throw std::invalid_argument(
        "prior bundle: distance matrix is " + std::to_string(bundle.distances.size()) + " x " +
        std::to_string(bundle.distances.size()) + " for " + std::to_string(n) + " guidepoints");
  GuidepointPrior prior;
  prior.prm_distance_m = CostMatrix(n, kUnreachable);
  for (const efs::prior_map::Guidepoint& g : bundle.guidepoints) {
    prior.ids.push_back(g.id);
    prior.positions_sketch_m.push_back(g.position_m);
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      prior.prm_distance_m(i, j) =
          bundle.distances.reachable(i, j) ? bundle.distances.at(i, j) : kUnreachable;
  const efs::prior_map::SketchFrame& f = bundle.frame;
  if (!bundle.traversable.empty()) {
    if (bundle.traversable.cols != f.width_px || bundle.traversable.rows != f.height_px)
      throw std::invalid_argument("prior bundle: traversable image is " +
                                  std::to_string(bundle.traversable.cols) + " x " +
                                  std::to_string(bundle.traversable.rows) + " px, frame " +
                                  std::to_string(f.width_px) + " x " + std::to_string(f.height_px));
    const int step = std::max(1, static_cast<int>(std::lround(spacing_m / f.m_per_px)));
    prior.predicted_free_cell_m = step * f.m_per_px;
    for (int row = step / 2; row < f.height_px; row += step)
      for (int col = step / 2; col < f.width_px; col += step)
        if (bundle.traversable(row, col) != 0)
          prior.predicted_free_sketch_m.push_back(f.pixelCenter(col, row));
  }
  prior.validate();
  return prior;
}

}  // namespace efs::planner
