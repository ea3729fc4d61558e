// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Worlds with closed-form ray casts: a hollow axis-aligned room with solid axis-aligned boxes
// (pillars, crates) inside. They let the simulator be checked against exact answers and give the
// benchmark a world whose ray cast cost is negligible, so that it measures the simulator alone.
#pragma once

#include <vector>

#include "marsim_worlds/world_geometry.h"

namespace efs::sim {

class AnalyticBoxWorld : public WorldGeometry {
 public:
  /// `room_world` is the hollow room: its six faces are walls, floor and ceiling. Rays leaving
  /// from outside the room hit its outer faces the same way.
  explicit AnalyticBoxWorld(const Eigen::AlignedBox3d& room_world);

  /// Adds a solid box (pillar, crate). Throws std::invalid_argument if it is empty.
  void addSolidBox(const Eigen::AlignedBox3d& box_world);

  const Eigen::AlignedBox3d& room() const { return room_; }
  const std::vector<Eigen::AlignedBox3d>& solidBoxes() const { return boxes_; }

  void castRays(const Eigen::Vector3d& origin_m, const std::vector<Eigen::Vector3f>& dirs_unit,
                double max_range_m, std::vector<float>* ranges_m) const override;
  /// Single ray, double precision; +infinity if nothing within `max_range_m`.
  double castRay(const Eigen::Vector3d& origin_m, const Eigen::Vector3d& dir_unit,
                 double max_range_m) const;
  bool collides(const Eigen::Vector3d& p_m, double radius_m) const override;
  Eigen::AlignedBox3d bounds() const override { return room_; }

  /// Distance from `p_m` to the nearest surface (walls or boxes); 0 inside a solid box.
  double distanceToSurface(const Eigen::Vector3d& p_m) const;

 private:
  Eigen::AlignedBox3d room_;
  std::vector<Eigen::AlignedBox3d> boxes_;
};

/// A closed room, `size_m` across, with its floor at z = 0 and its centre at x = y = 0.
AnalyticBoxWorld makeBoxRoom(const Eigen::Vector3d& size_m);

/// The same room with one square pillar of side `pillar_side_m` from floor to ceiling, centred
/// at (`pillar_x_m`, `pillar_y_m`).
AnalyticBoxWorld makeRoomWithPillar(const Eigen::Vector3d& size_m, double pillar_x_m,
                                    double pillar_y_m, double pillar_side_m);

/// A hall of `size_m` with a regular grid of square pillars (a garage-like analytic world for the
/// benchmark); pillars every `spacing_m`, leaving a free margin of `spacing_m / 2` along walls.
AnalyticBoxWorld makePillarHall(const Eigen::Vector3d& size_m, double spacing_m,
                                double pillar_side_m);

}  // namespace efs::sim
