// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/viewpoint_attachment.h"

#include <limits>
#include <stdexcept>

#include "efs_common/config_check.h"

namespace efs::planner {

void AttachmentConfig::validate() const {
  requirePositive("attachment.rho_m", rho_m);
  requirePositive("attachment.influence_radius_m", influence_radius_m);
  requireInRange("attachment.outside_margin_m", outside_margin_m, 0.0, 1e9);
  requireInRange("attachment.seen_fraction", seen_fraction, 0.0, 1.0);
  requireInRange("attachment.seen_keep_radius_m", seen_keep_radius_m, 0.0, 1e4);
}

const char* toString(GuidepointState s) {
  switch (s) {
    case GuidepointState::kUnexplored:
      return "unexplored";
    case GuidepointState::kExploring:
      return "exploring";
    case GuidepointState::kExplored:
      return "explored";
    case GuidepointState::kOutside:
      return "outside";
  }
  return "unknown";
}

HypothesisAttachment attachViewpoints(const Hypothesis& hypothesis, const GuidepointPrior& prior,
                                      const std::vector<PlanViewpoint>& viewpoints,
                                      const ObservationQuery& observation,
                                      const std::optional<Eigen::AlignedBox2d>& bounds_world_m,
                                      const AttachmentConfig& config,
                                      const std::optional<Eigen::Vector2d>& robot_xy_world_m) {
  config.validate();
  if (const auto why = hypothesisDefect(hypothesis))
    throw std::invalid_argument("attachViewpoints: hypothesis " + std::to_string(hypothesis.id) +
                                " unusable: " + *why);
  const int ng = prior.size(), nv = static_cast<int>(viewpoints.size());
  HypothesisAttachment out;
  out.guidepoints_world_m.resize(ng);
  out.states.assign(ng, GuidepointState::kUnexplored);
  out.attached.assign(ng, {});
  out.attached_to.assign(nv, -1);
  std::vector<char> active(ng, 1);
  for (int j = 0; j < ng; ++j) {
    out.guidepoints_world_m[j] = hypothesis.T_world_sketch.apply(prior.positions_sketch_m[j]);
    if (bounds_world_m && !bounds_world_m->isEmpty()) {
      const double d =
          std::sqrt(bounds_world_m->squaredExteriorDistance(out.guidepoints_world_m[j]));
      if (d > config.outside_margin_m) out.states[j] = GuidepointState::kOutside, active[j] = 0;
    }
  }
  // The guidepoint a point in the world attaches to, by the paper's rule; -1 for none.
  const auto nearest = [&](const Eigen::Vector2d& p) {
    double d1 = std::numeric_limits<double>::infinity(), d2 = d1;
    int j1 = -1;
    for (int j = 0; j < ng; ++j) {
      if (!active[j]) continue;
      const double d = (out.guidepoints_world_m[j] - p).norm();
      if (d < d1)
        d2 = d1, d1 = d, j1 = j;
      else if (d < d2)
        d2 = d;
    }
    return j1 >= 0 && d1 < std::min(config.rho_m, d2) ? j1 : -1;
  };
  for (int i = 0; i < nv; ++i) {
    const int j = nearest(viewpoints[i].position_world_m.head<2>());
    if (j < 0) continue;
    out.attached_to[i] = j;
    out.attached[j].push_back(i);
  }
  // Per guidepoint, its predicted free samples and how many of them are well observed.
  std::vector<int> samples(ng, 0), seen(ng, 0);
  if (config.seen_fraction > 0.0 && observation) {
    const double r = 0.5 * hypothesis.T_world_sketch.scale * prior.predicted_free_cell_m;
    for (const Eigen::Vector2d& s : prior.predicted_free_sketch_m) {
      const Eigen::Vector2d w = hypothesis.T_world_sketch.apply(s);
      const int j = nearest(w);
      if (j < 0) continue;
      ++samples[j];
      seen[j] += observation(w, r) == ObservationLevel::kWellObserved;
    }
  }
  const auto besideRobot = [&](int j) {
    if (!robot_xy_world_m || !(config.seen_keep_radius_m > 0.0)) return false;
    for (int i : out.attached[j])
      if ((viewpoints[i].position_world_m.head<2>() - *robot_xy_world_m).norm() <=
          config.seen_keep_radius_m)
        return true;
    return false;
  };
  for (int j = 0; j < ng; ++j) {
    if (!active[j]) continue;
    if (samples[j] > 0 && seen[j] >= config.seen_fraction * samples[j] && !besideRobot(j)) {
      out.states[j] = GuidepointState::kExplored;
    } else if (!out.attached[j].empty()) {
      out.states[j] = GuidepointState::kExploring;
    } else if (observation && observation(out.guidepoints_world_m[j], config.influence_radius_m) ==
                                  ObservationLevel::kWellObserved) {
      out.states[j] = GuidepointState::kExplored;
    }
  }
  return out;
}

}  // namespace efs::planner
