// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// What the simulator needs from a world: ray casting for the LiDAR, collision checks for the
// vehicle, and its extent. Worlds (generated, imported) implement it; tests implement it with
// analytic scenes so that the simulator can be checked against closed-form answers.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <limits>
#include <vector>

namespace efs::sim {

class WorldGeometry {
 public:
  virtual ~WorldGeometry() = default;

  /// Casts rays from one origin. `dirs_unit` are unit vectors in the world frame. On return
  /// `ranges_m` has one entry per ray: the distance to the first occupied surface, or
  /// +infinity if nothing lies within `max_range_m`.
  virtual void castRays(const Eigen::Vector3d& origin_m,
                        const std::vector<Eigen::Vector3f>& dirs_unit, double max_range_m,
                        std::vector<float>* ranges_m) const = 0;

  /// True if a sphere of `radius_m` around `p_m` intersects an occupied part of the world, or
  /// leaves the world's bounds.
  virtual bool collides(const Eigen::Vector3d& p_m, double radius_m) const = 0;

  /// Axis-aligned extent of the world (the exploration bounding box by default).
  virtual Eigen::AlignedBox3d bounds() const = 0;

  static constexpr float kNoHit = std::numeric_limits<float>::infinity();
};

}  // namespace efs::sim
