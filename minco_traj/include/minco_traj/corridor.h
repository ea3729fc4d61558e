// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Safe flight corridor: one convex polytope (H-representation A x <= b, unit-norm rows) per seed
// segment of the front-end path, grown by alternating half-space and ellipsoid steps in the
// manner of IRIS / FIRI (Deits & Tedrake 2015; Wang et al., "Fast Iterative Region Inflation",
// 2025). Our variant, chosen for soundness with a simple implementation:
//   1. Half-space step. Obstacle points (occupied cell centres) are visited in order of their
//      distance to the current ellipsoid E = {C u + d : |u| <= 1} in E's own metric. The nearest
//      unhandled point o gets the plane tangent to the scaled ellipsoid through o (IRIS). If that
//      plane, moved inward by clearance_m, would leave the seed segment less than half of the
//      margin dist(o, seed) - clearance_m, the plane through o perpendicular to the segment-to-o
//      direction is used instead (FIRI's requirement that the seed stays inside, with room). All
//      points on or beyond the plane are handled. Each plane is then moved inward by clearance_m,
//      but never past the seed (the polytope is flagged clearance_reduced when that limit binds).
//      Obstacles up to clearance_m outside the seed's box are included, so the box faces keep the
//      clearance too.
//   2. Ellipsoid step. The maximum-volume ellipsoid inscribed in the polytope, by a log-barrier
//      Newton method on (L lower triangular, d): maximise log det L s.t. |L^T a_i| + a_i.d <= b_i
//      (two points of the central path; Hessian by differences of the analytic gradient). It is
//      skipped after the last half-space step.
// Unlike FIRI we do not prove monotone volume growth; two alternations (the default) already give
// regions that reach the nearby obstacles (test: RegionGrowsIntoFreeSpace). Interior occupied
// cells are skipped when clearance_m >= 2 cells, and each polytope is limited to its seed's box
// plus box_margin_m, which keeps the cost near-linear in the path length.
// Guarantees by construction: the seed segment lies in its polytope, every obstacle point is at
// least clearance_m (or the reduced clearance) outside it, and consecutive polytopes share the
// path vertex between their seeds, so they overlap.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "minco_traj/local_grid.h"

namespace efs::traj {

struct Polytope {
  Eigen::Matrix<double, Eigen::Dynamic, 3> A;  ///< unit outward normals, one per row
  Eigen::VectorXd b;
  Eigen::Vector3d seed_start_m = Eigen::Vector3d::Zero(), seed_end_m = Eigen::Vector3d::Zero();
  /// The ellipsoid E = {C u + d, |u| <= 1} that ordered the last half-space step (the previous
  /// polytope's inscribed ellipsoid). Tangent planes keep it inside; a seed-protecting plane may
  /// cut it, so it is a shape hint for visualisation, not a guaranteed inner region.
  Eigen::Matrix3d ellipsoid_C = Eigen::Matrix3d::Identity();
  Eigen::Vector3d ellipsoid_d = Eigen::Vector3d::Zero();
  bool clearance_reduced = false;

  /// max_i (a_i . p - b_i): <= 0 inside.
  double violation(const Eigen::Vector3d& p) const;
  bool contains(const Eigen::Vector3d& p, double tol_m = 1e-9) const {
    return violation(p) <= tol_m;
  }
  int planeCount() const { return static_cast<int>(b.size()); }
};

struct CorridorConfig {
  double clearance_m = 0.45;       ///< obstacles stay this far outside (the vehicle radius)
  double box_margin_m = 1.0;       ///< each polytope lies in the seed's bounding box + margin
  double max_seed_length_m = 4.0;  ///< longer path segments are split into several seeds
  /// Unobserved cells more than this below the seed path are obstacles (build from a grid); 0 =
  /// off, else more than clearance_m. The LiDAR does not look down (the Mid-360, pitched 15 deg,
  /// sees nothing more than 22 deg below the horizon), so the ground ahead of a descent is often
  /// unseen; with only occupied cells as obstacles a polytope reached 1 m under the path, and the
  /// trajectory passed 0.09 m from an unseen rock 1.2 m below and 1.5 m ahead of the vehicle
  /// (paper-size cave, prior-free flight, collision at 283.8 s). With 0.7 a polytope ends about
  /// blind_depth_m - clearance_m (0.25 m) below the path over unseen ground.
  double blind_depth_m = 0.7;
  int iterations = 2;             ///< half-space / ellipsoid alternations
  double initial_radius_m = 0.3;  ///< cross radius of the first ellipsoid around the seed
  int mvie_newton_steps = 25;
  void validate() const;
};

enum class CorridorStatus { kOk, kEmptyPath, kSeedInCollision };
const char* toString(CorridorStatus s);

struct CorridorResult {
  CorridorStatus status = CorridorStatus::kEmptyPath;
  std::vector<Polytope> polytopes;
  bool ok() const { return status == CorridorStatus::kOk; }
};

class CorridorBuilder {
 public:
  explicit CorridorBuilder(const CorridorConfig& cfg = {});

  /// Corridor along a front-end path, obstacles from the grid's occupied cells; polytopes are
  /// also bounded by the grid window.
  CorridorResult build(const std::vector<Eigen::Vector3d>& path_world_m,
                       const LocalGrid& grid) const;
  /// Same with explicit obstacle points and bounds (the polytopes stay inside [lo, hi]).
  CorridorResult build(const std::vector<Eigen::Vector3d>& path_world_m,
                       const std::vector<Eigen::Vector3d>& obstacles_world_m,
                       const Eigen::Vector3d& bound_lo, const Eigen::Vector3d& bound_hi) const;

  /// One polytope around the segment [a, b]; `in_collision` is set if an obstacle lies on it.
  Polytope inflateSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const std::vector<Eigen::Vector3d>& obstacles,
                          const Eigen::Vector3d& bound_lo, const Eigen::Vector3d& bound_hi,
                          bool* in_collision) const;

  /// Splits a path into seed segments (dropping repeated points, splitting long segments).
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> seeds(
      const std::vector<Eigen::Vector3d>& path) const;

 private:
  CorridorConfig cfg_;
};

/// Maximum-volume inscribed ellipsoid of {x : A x <= b} from a strictly interior point x0.
/// Returns false if x0 is not strictly inside. Exposed for tests.
bool maxVolumeInscribedEllipsoid(const Eigen::Matrix<double, Eigen::Dynamic, 3>& A,
                                 const Eigen::VectorXd& b, const Eigen::Vector3d& x0,
                                 int newton_steps, Eigen::Matrix3d* C, Eigen::Vector3d* d);

}  // namespace efs::traj
