// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Deterministic synthetic 2D floor plans (walls as line segments) and a LiDAR-like observer that
// accumulates a 3D local map of them, for tests and benchmarks of the registration. Not a
// simulator (marsim_worlds is): only what the registration needs to be exercised end to end.
#pragma once

#include <cstdint>
#include <random>
#include <unordered_set>
#include <vector>

#include "efs_common/sim2.h"
#include "sketch_registration/types.h"

namespace efs::registration::synthetic {

struct Segment {
  Eigen::Vector2d a, b;
};
using FloorPlan = std::vector<Segment>;
/// Solid (non-traversable) axis-aligned boxes of a plan: pillars, service cores.
struct Box {
  Eigen::Vector2d min_m, max_m;
  bool contains(const Eigen::Vector2d& p) const {
    return p.x() >= min_m.x() && p.y() >= min_m.y() && p.x() <= max_m.x() && p.y() <= max_m.y();
  }
};

/// Four walls of an axis-aligned box.
void addBox(FloorPlan& plan, const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m);
/// A straight wall from a to b with a door gap of `door_m` centred at fraction `at` (0..1).
void addWallWithDoor(FloorPlan& plan, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double at,
                     double door_m);

/// An asymmetric office-like floor of about 60 x 40 m: rooms of different sizes off an L-shaped
/// corridor, with doors. `bounds_min/max` receive the outer box.
FloorPlan makeOfficeFloor(Eigen::Vector2d* bounds_min = nullptr,
                          Eigen::Vector2d* bounds_max = nullptr,
                          std::vector<Box>* solids = nullptr);
/// A parking-garage-like floor of about 190 x 150 m: outer walls, a grid of pillars, ramps and
/// service cores (seeded irregularity so that places differ).
FloorPlan makeGarageFloor(uint64_t seed, Eigen::Vector2d* bounds_min = nullptr,
                          Eigen::Vector2d* bounds_max = nullptr,
                          std::vector<Box>* solids = nullptr);

FloorPlan transformed(const FloorPlan& plan, const Sim2& T);
Points2d samplePlan(const FloorPlan& plan, double spacing_m);
double distanceToPlan(const FloorPlan& plan, const Eigen::Vector2d& p);
/// Traversable: inside [min, max], outside every solid box and `clearance_m` from every wall.
/// Walls are bucketed once, so this is cheap enough to build a 20k-candidate grid.
class TraversabilityCheck {
 public:
  TraversabilityCheck(const FloorPlan& plan, const std::vector<Box>& solids,
                      const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m,
                      double clearance_m);
  bool operator()(const Eigen::Vector2d& p) const;

 private:
  std::vector<Box> solids_;
  Eigen::Vector2d min_m_, max_m_;
  double clearance_m_;
  double cell_m_;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<Segment>> cells_;
};
/// First hits of `num_rays` rays from `origin` within `max_range_m`.
Points2d castRays(const FloorPlan& plan, const Eigen::Vector2d& origin, int num_rays,
                  double max_range_m);

/// Accumulates what a LiDAR at `height_m` sees: wall hits extruded over the wall height, a few
/// floor and ceiling returns, Gaussian noise; a 0.1 m voxel set keeps the map bounded.
class LocalMapSimulator {
 public:
  struct Config {
    double range_m = 30.0;
    int num_rays = 360;
    double wall_height_m = 3.0;
    double noise_m = 0.03;
    double voxel_m = 0.1;
    double floor_ceiling_fraction = 0.3;  ///< per wall point, chance of a floor/ceiling return
    uint64_t seed = 7;
  };
  LocalMapSimulator(FloorPlan world_plan, const Config& config);
  void scanAt(const Eigen::Vector2d& robot_world_m);
  /// Points within `radius_m` (horizontal) of `center`.
  Points3d localMap(const Eigen::Vector2d& center_m, double radius_m) const;
  size_t size() const { return points_.size(); }

 private:
  FloorPlan plan_;
  Config config_;
  std::mt19937_64 rng_;
  std::unordered_set<long long> seen_;
  Points3d points_;
};

/// Points along a polyline every `step_m`.
Points2d samplePath(const Points2d& waypoints, double step_m);

/// A ready-to-run registration scene: the sketch (plan, boundary points, candidate grid) in the
/// sketch frame, the true sketch->world transform and a robot path in the world frame.
struct Scenario {
  FloorPlan sketch_plan;
  Points2d sketch_points_m;
  Points2d candidates_m;
  Sim2 T_world_sketch;
  FloorPlan world_plan;
  Points2d path_world_m;  ///< one point every path_step_m
};
/// `waypoints_sketch_m` route the robot in sketch coordinates (easy to draw), mapped to the world.
Scenario makeScenario(const FloorPlan& plan, const std::vector<Box>& solids,
                      const Eigen::Vector2d& bounds_min, const Eigen::Vector2d& bounds_max,
                      const Sim2& T_world_sketch, const Points2d& waypoints_sketch_m,
                      double sketch_spacing_m = 0.1, double d_gap_m = 1.0,
                      double path_step_m = 2.0);

}  // namespace efs::registration::synthetic
