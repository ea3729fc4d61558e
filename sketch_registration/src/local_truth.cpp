// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/local_truth.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace efs::registration {

double placementRms(const Points2d& sketch_m, const Sim2& a, const Sim2& b) {
  double sum = 0.0;
  for (const Eigen::Vector2d& q : sketch_m) sum += (a.apply(q) - b.apply(q)).squaredNorm();
  return sketch_m.empty() ? std::nan("") : std::sqrt(sum / static_cast<double>(sketch_m.size()));
}

LocalTruth::LocalTruth(const Points2d& world_m, const Points2d& sketch_m, double radius_m,
                       bool reflected, double max_stretch)
    : sketch_m_(sketch_m), radius_m_(radius_m), reflected_(reflected), max_stretch_(max_stretch) {
  if (world_m.size() != sketch_m.size()) {
    throw std::invalid_argument("LocalTruth: " + std::to_string(world_m.size()) +
                                " world points but " + std::to_string(sketch_m.size()) +
                                " sketch points");
  }
  if (!(radius_m > 0.0)) throw std::invalid_argument("LocalTruth: radius_m must be positive");
  if (!(max_stretch >= 1.0)) throw std::invalid_argument("LocalTruth: max_stretch must be >= 1");
  world_tree_ =
      std::make_unique<PointKdTree<2>>(PointKdTree<2>::Points(world_m.begin(), world_m.end()));
  is_seen_.assign(world_m.size(), 0);
}

void LocalTruth::observeFrom(const Eigen::Vector2d& robot_m) {
  if (!robot_m.allFinite()) return;
  for (const auto& hit : world_tree_->radius(robot_m, radius_m_)) {
    const size_t i = hit.first;
    if (is_seen_[i]) continue;
    is_seen_[i] = 1;
    seen_sketch_m_.push_back(sketch_m_[i]);
    seen_world_m_.push_back(world_tree_->points()[i]);
  }
}

const std::optional<Sim2Fit>& LocalTruth::fit() const {
  if (seen_sketch_m_.size() == cached_count_) return cached_;
  cached_count_ = seen_sketch_m_.size();
  cached_.reset();
  if (seen_sketch_m_.size() < 2) return cached_;
  const Sim2Fit f =
      fitStretchedSim2(seen_sketch_m_, seen_world_m_, reflected_, 0.0, 1e300, max_stretch_);
  if (f.ok) cached_ = f;
  return cached_;
}

double LocalTruth::placementRms(const Sim2& T) const {
  const std::optional<Sim2Fit>& local = fit();
  return local ? registration::placementRms(seen_sketch_m_, T, local->T_world_sketch)
               : std::nan("");
}

}  // namespace efs::registration
