// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The true placement of a deformed drawing over the part of the world seen so far, for
// evaluation only (registration_eval). A deformed drawing has no single true similarity: the
// generator's sidecar holds the best one over the whole drawing, and on the paper-size garage
// (192 x 150 m, warped by up to 4 m and stretched up to 8 % along one axis) that one lies metres
// off the walls around the robot, where no registration can see it. Given each drawn wall's
// world position and where the drawing put it, LocalTruth fits the similarity over the pairs
// whose world point lies within radius_m of the route flown so far: what a registration of the
// walls seen can be asked to find. It is fitted in the registration's own family: a similarity,
// or with a stretch of at most max_stretch where the registration refines one.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "efs_common/point_kdtree.h"
#include "efs_common/sim2.h"
#include "sketch_registration/sim2_fit.h"
#include "sketch_registration/types.h"

namespace efs::registration {

/// RMS of |a(q) - b(q)| over the sketch points q: how far two placements of a drawing lie apart
/// (world metres). Unlike closest-pair distances, a shrunken or shifted placement cannot hide
/// among dense walls. NaN for no points.
double placementRms(const Points2d& sketch_m, const Sim2& a, const Sim2& b);

class LocalTruth {
 public:
  /// `world_m[i]` was drawn at `sketch_m[i]`; `reflected`: the drawing is a mirror image.
  /// Throws std::invalid_argument on sizes that differ, a radius that is not positive or a
  /// max_stretch below 1.
  LocalTruth(const Points2d& world_m, const Points2d& sketch_m, double radius_m, bool reflected,
             double max_stretch = 1.0);

  /// Marks the pairs whose world point lies within radius_m of `robot_m` as seen.
  void observeFrom(const Eigen::Vector2d& robot_m);
  size_t seenCount() const { return seen_sketch_m_.size(); }

  /// The least-squares transform (similarity, or bounded stretch) over the seen pairs; empty until
  /// two of them are seen or while they are degenerate (all at one point).
  const std::optional<Sim2Fit>& fit() const;

  /// RMS of |T(q) - T_local(q)| over the seen pairs' sketch points q: the placement error of T
  /// where it can be judged. NaN while fit() is empty.
  double placementRms(const Sim2& T) const;

 private:
  Points2d sketch_m_;
  std::unique_ptr<PointKdTree<2>> world_tree_;
  double radius_m_;
  bool reflected_;
  double max_stretch_;
  std::vector<uint8_t> is_seen_;
  Points2d seen_sketch_m_, seen_world_m_;  ///< the pairs seen, in the order first seen
  mutable std::optional<Sim2Fit> cached_;
  mutable size_t cached_count_ = 0;
};

}  // namespace efs::registration
