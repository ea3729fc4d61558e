// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/prior_from_bundle.h"

#include <stdexcept>
#include <string>

namespace efs::planner {

GuidepointPrior guidepointPriorFromBundle(const efs::prior_map::PriorBundle& bundle) {
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
  prior.validate();
  return prior;
}

}  // namespace efs::planner
