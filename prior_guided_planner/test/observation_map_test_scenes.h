// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Analytic scenes for the observation-map, frontier, viewpoint and path-length tests: one room
// (the inside of a box) with solid boxes in it, and a ray caster that turns a sensor pose into
// a registered scan (world-frame points), the way the LIO front end hands them to the planner.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace efs::planner::testing {

/// A grazing limit of 17.5 deg (the default before 0.05). One scan of a room then leaves the
/// walls and floor it sees at shallow angles poorly observed, so even a short room holds several
/// frontier clusters; tests about what is done with clusters pin it.
constexpr double kStrictFacingMinCosine = 0.3;

struct Box {
  Eigen::Vector3d lo, hi;
};

struct Scene {
  Box room;                 ///< rays from inside hit its walls from within
  std::vector<Box> solids;  ///< obstacles (hit from outside)

  /// Distance along unit `d` from `o` to the first surface, +inf when none.
  double cast(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double t_best = kInf;
    for (int i = 0; i < 3; ++i) {
      if (d[i] > 0) t_best = std::min(t_best, (room.hi[i] - o[i]) / d[i]);
      if (d[i] < 0) t_best = std::min(t_best, (room.lo[i] - o[i]) / d[i]);
    }
    for (const Box& b : solids) {
      double t0 = 0.0, t1 = kInf;
      bool miss = false;
      for (int i = 0; i < 3 && !miss; ++i) {
        if (d[i] == 0.0) {
          miss = o[i] < b.lo[i] || o[i] > b.hi[i];
          continue;
        }
        double a = (b.lo[i] - o[i]) / d[i], c = (b.hi[i] - o[i]) / d[i];
        if (a > c) std::swap(a, c);
        t0 = std::max(t0, a);
        t1 = std::min(t1, c);
        miss = t0 > t1;
      }
      if (!miss && t0 > 0.0) t_best = std::min(t_best, t0);
    }
    return t_best;
  }

  /// Full-sphere scan with `step_deg` spacing in azimuth and elevation.
  std::vector<Eigen::Vector3d> scanSphere(const Eigen::Vector3d& o, double step_deg,
                                          double max_range_m = 100.0) const {
    std::vector<Eigen::Vector3d> pts;
    const double k = 3.14159265358979323846 / 180.0;
    for (double el = -90.0 + 0.5 * step_deg; el < 90.0; el += step_deg) {
      for (double az = 0.0; az < 360.0; az += step_deg) {
        const Eigen::Vector3d d(std::cos(el * k) * std::cos(az * k),
                                std::cos(el * k) * std::sin(az * k), std::sin(el * k));
        const double t = cast(o, d);
        if (t <= max_range_m) pts.push_back(o + t * d);
      }
    }
    return pts;
  }
};

/// A hollow closed box with walls `wall_m` thick, as six solid slabs.
inline std::vector<Box> hollowBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                  double wall_m) {
  std::vector<Box> out;
  for (int axis = 0; axis < 3; ++axis) {
    Box a{lo, hi}, b{lo, hi};
    a.hi[axis] = lo[axis] + wall_m;
    b.lo[axis] = hi[axis] - wall_m;
    out.push_back(a);
    out.push_back(b);
  }
  return out;
}

/// A hall of 20 x 8 x 3 m split at x = 5 by a wall with a 1.2 m door, a crate in its left part.
inline Scene doorHall() {
  Scene scene;
  scene.room = {{-5, -4, 0}, {15, 4, 3}};
  scene.solids.push_back({{5.0, -4, 0}, {5.3, -0.6, 3}});
  scene.solids.push_back({{5.0, 0.6, 0}, {5.3, 4, 3}});
  scene.solids.push_back({{1.0, 2.0, 0}, {2.0, 3.0, 0.8}});
  return scene;
}

/// doorHall() flown from its left part through the door into its right one, a point every
/// `step_m` along x.
inline std::vector<Eigen::Vector3d> doorHallRoute(double step_m) {
  std::vector<Eigen::Vector3d> r;
  for (double x = -3.0; x <= 10.0; x += step_m) r.push_back({x, 0.1 * x, 1.2 + 0.05 * x});
  return r;
}

}  // namespace efs::planner::testing
