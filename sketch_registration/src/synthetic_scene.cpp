// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/synthetic_scene.h"

#include <algorithm>
#include <cmath>

#include "sketch_registration/candidate_database.h"

namespace efs::registration::synthetic {

using Eigen::Vector2d;

void addBox(FloorPlan& plan, const Vector2d& lo, const Vector2d& hi) {
  plan.push_back({{lo.x(), lo.y()}, {hi.x(), lo.y()}});
  plan.push_back({{hi.x(), lo.y()}, {hi.x(), hi.y()}});
  plan.push_back({{hi.x(), hi.y()}, {lo.x(), hi.y()}});
  plan.push_back({{lo.x(), hi.y()}, {lo.x(), lo.y()}});
}

void addWallWithDoor(FloorPlan& plan, const Vector2d& a, const Vector2d& b, double at,
                     double door_m) {
  const double len = (b - a).norm();
  const Vector2d u = (b - a) / len;
  const double c = at * len;
  const double g0 = std::max(0.0, c - 0.5 * door_m), g1 = std::min(len, c + 0.5 * door_m);
  if (g0 > 1e-6) plan.push_back({a, a + g0 * u});
  if (len - g1 > 1e-6) plan.push_back({a + g1 * u, b});
}

FloorPlan makeOfficeFloor(Vector2d* bmin, Vector2d* bmax, std::vector<Box>* solids) {
  FloorPlan p;
  const Vector2d lo(0, 0), hi(60, 40);
  addBox(p, lo, hi);
  // L-shaped corridor: horizontal band y in [16, 20], vertical band x in [40, 44] above it.
  // South rooms (below the corridor), of unequal widths.
  addWallWithDoor(p, {0, 16}, {12, 16}, 0.5, 1.2);
  addWallWithDoor(p, {12, 16}, {30, 16}, 0.3, 1.2);
  addWallWithDoor(p, {30, 16}, {60, 16}, 0.7, 1.2);
  p.push_back({{12, 0}, {12, 16}});
  p.push_back({{30, 0}, {30, 16}});
  p.push_back({{48, 6}, {48, 16}});  // partial wall inside the big south-east room
  addBox(p, {20, 4}, {24, 8});       // a pillar block in a south room
  // North side: corridor wall y = 20 from x = 0 to 40, then the vertical corridor.
  addWallWithDoor(p, {0, 20}, {18, 20}, 0.6, 1.2);
  addWallWithDoor(p, {18, 20}, {40, 20}, 0.4, 1.2);
  addWallWithDoor(p, {40, 20}, {40, 40}, 0.5, 1.2);
  addWallWithDoor(p, {44, 20}, {44, 40}, 0.3, 1.2);
  p.push_back({{44, 20}, {60, 20}});
  p.push_back({{18, 20}, {18, 40}});
  p.push_back({{44, 30}, {60, 30}});
  p.push_back({{0, 31}, {8, 31}});  // a short wall in the north-west room
  addBox(p, {52, 34}, {55, 37});    // a column in the north-east room
  if (solids) *solids = {{{20, 4}, {24, 8}}, {{52, 34}, {55, 37}}};
  if (bmin) *bmin = lo;
  if (bmax) *bmax = hi;
  return p;
}

FloorPlan makeGarageFloor(uint64_t seed, Vector2d* bmin, Vector2d* bmax, std::vector<Box>* solids) {
  FloorPlan p;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vector2d lo(0, 0), hi(190, 150);
  addBox(p, lo, hi);
  // Service cores and ramps: blocked areas that make places distinguishable.
  const std::vector<std::pair<Vector2d, Vector2d>> blocks = {{{20, 60}, {45, 80}},
                                                             {{120, 20}, {150, 35}},
                                                             {{90, 100}, {100, 140}},
                                                             {{160, 110}, {185, 120}},
                                                             {{60, 10}, {70, 30}}};
  for (const auto& b : blocks) addBox(p, b.first, b.second);
  if (solids) {
    solids->clear();
    for (const auto& b : blocks) solids->push_back({b.first, b.second});
  }
  auto blocked = [&](const Vector2d& q, double margin) {
    for (const auto& b : blocks) {
      if (q.x() > b.first.x() - margin && q.x() < b.second.x() + margin &&
          q.y() > b.first.y() - margin && q.y() < b.second.y() + margin) {
        return true;
      }
    }
    return false;
  };
  // Pillars every 8 m with seeded gaps; partial walls between some.
  for (double x = 8; x < 186; x += 8.0) {
    for (double y = 8; y < 146; y += 8.0) {
      const Vector2d c(x, y);
      if (blocked(c, 2.0) || u(rng) < 0.15) continue;
      addBox(p, c - Vector2d(0.3, 0.3), c + Vector2d(0.3, 0.3));
      if (solids) solids->push_back({c - Vector2d(0.3, 0.3), c + Vector2d(0.3, 0.3)});
      if (u(rng) < 0.08) p.push_back({c + Vector2d(0.3, 0), c + Vector2d(7.7, 0)});
    }
  }
  if (bmin) *bmin = lo;
  if (bmax) *bmax = hi;
  return p;
}

FloorPlan transformed(const FloorPlan& plan, const Sim2& T) {
  FloorPlan out;
  out.reserve(plan.size());
  for (const auto& s : plan) out.push_back({T.apply(s.a), T.apply(s.b)});
  return out;
}

Points2d samplePlan(const FloorPlan& plan, double spacing_m) {
  Points2d out;
  for (const auto& s : plan) {
    const double len = (s.b - s.a).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(len / spacing_m)));
    for (int i = 0; i <= n; ++i) out.push_back(s.a + (s.b - s.a) * (double(i) / n));
  }
  return out;
}

double distanceToPlan(const FloorPlan& plan, const Vector2d& p) {
  double best = 1e300;
  for (const auto& s : plan) {
    const Vector2d d = s.b - s.a;
    const double t = std::clamp((p - s.a).dot(d) / std::max(1e-12, d.squaredNorm()), 0.0, 1.0);
    best = std::min(best, (s.a + t * d - p).norm());
  }
  return best;
}

namespace {
double segmentDistance(const Segment& s, const Vector2d& p) {
  const Vector2d d = s.b - s.a;
  const double t = std::clamp((p - s.a).dot(d) / std::max(1e-12, d.squaredNorm()), 0.0, 1.0);
  return (s.a + t * d - p).norm();
}
}  // namespace

TraversabilityCheck::TraversabilityCheck(const FloorPlan& plan, const std::vector<Box>& solids,
                                         const Vector2d& min_m, const Vector2d& max_m,
                                         double clearance_m)
    : solids_(solids),
      min_m_(min_m),
      max_m_(max_m),
      clearance_m_(clearance_m),
      cell_m_(std::max(2.0, 4.0 * clearance_m)) {
  nx_ = static_cast<int>((max_m.x() - min_m.x()) / cell_m_) + 1;
  ny_ = static_cast<int>((max_m.y() - min_m.y()) / cell_m_) + 1;
  cells_.resize(static_cast<size_t>(nx_) * ny_);
  // A segment goes into every cell whose box, grown by the clearance, it may touch.
  for (const auto& s : plan) {
    const Vector2d lo = s.a.cwiseMin(s.b).array() - clearance_m;
    const Vector2d hi = s.a.cwiseMax(s.b).array() + clearance_m;
    const int x0 = std::max(0, static_cast<int>(std::floor((lo.x() - min_m.x()) / cell_m_)));
    const int x1 = std::min(nx_ - 1, static_cast<int>(std::floor((hi.x() - min_m.x()) / cell_m_)));
    const int y0 = std::max(0, static_cast<int>(std::floor((lo.y() - min_m.y()) / cell_m_)));
    const int y1 = std::min(ny_ - 1, static_cast<int>(std::floor((hi.y() - min_m.y()) / cell_m_)));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) cells_[static_cast<size_t>(y) * nx_ + x].push_back(s);
    }
  }
}

bool TraversabilityCheck::operator()(const Vector2d& p) const {
  if (p.x() < min_m_.x() || p.y() < min_m_.y() || p.x() > max_m_.x() || p.y() > max_m_.y()) {
    return false;
  }
  for (const Box& b : solids_) {
    if (b.contains(p)) return false;
  }
  const int x = std::min(nx_ - 1, static_cast<int>((p.x() - min_m_.x()) / cell_m_));
  const int y = std::min(ny_ - 1, static_cast<int>((p.y() - min_m_.y()) / cell_m_));
  for (const Segment& s : cells_[static_cast<size_t>(y) * nx_ + x]) {
    if (segmentDistance(s, p) < clearance_m_) return false;
  }
  return true;
}

Points2d castRays(const FloorPlan& plan, const Vector2d& o, int num_rays, double max_range_m) {
  Points2d out;
  // Only segments that can be within range.
  std::vector<const Segment*> near;
  for (const auto& s : plan) {
    const Vector2d d = s.b - s.a;
    const double t = std::clamp((o - s.a).dot(d) / std::max(1e-12, d.squaredNorm()), 0.0, 1.0);
    if ((s.a + t * d - o).norm() <= max_range_m) near.push_back(&s);
  }
  for (int k = 0; k < num_rays; ++k) {
    const double a = 2.0 * M_PI * k / num_rays;
    const Vector2d r(std::cos(a), std::sin(a));
    double best = max_range_m;
    bool hit = false;
    for (const Segment* s : near) {
      const Vector2d e = s->b - s->a;
      const double den = r.x() * e.y() - r.y() * e.x();
      if (std::abs(den) < 1e-12) continue;
      const Vector2d w = s->a - o;
      const double t = (w.x() * e.y() - w.y() * e.x()) / den;  // along the ray
      const double v = (w.x() * r.y() - w.y() * r.x()) / den;  // along the segment
      if (t > 1e-6 && t < best && v >= 0.0 && v <= 1.0) {
        best = t;
        hit = true;
      }
    }
    if (hit) out.push_back(o + best * r);
  }
  return out;
}

LocalMapSimulator::LocalMapSimulator(FloorPlan world_plan, const Config& config)
    : plan_(std::move(world_plan)), config_(config), rng_(config.seed) {}

void LocalMapSimulator::scanAt(const Vector2d& robot) {
  std::normal_distribution<double> noise(0.0, config_.noise_m);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto add = [&](const Eigen::Vector3d& q) {
    const long long ix = static_cast<long long>(std::floor(q.x() / config_.voxel_m));
    const long long iy = static_cast<long long>(std::floor(q.y() / config_.voxel_m));
    const long long iz = static_cast<long long>(std::floor(q.z() / config_.voxel_m));
    const long long key = (ix * 73856093LL) ^ (iy * 19349663LL) ^ (iz * 83492791LL);
    if (seen_.insert(key).second) points_.push_back(q);
  };
  for (const Vector2d& h : castRays(plan_, robot, config_.num_rays, config_.range_m)) {
    for (double z = 0.25; z < config_.wall_height_m; z += 0.5) {
      add({h.x() + noise(rng_), h.y() + noise(rng_), z + noise(rng_)});
    }
    if (u(rng_) < config_.floor_ceiling_fraction) {
      const Vector2d f = robot + u(rng_) * (h - robot);
      add({f.x(), f.y(), (u(rng_) < 0.5 ? 0.0 : config_.wall_height_m) + noise(rng_)});
    }
  }
}

Points3d LocalMapSimulator::localMap(const Vector2d& c, double radius_m) const {
  Points3d out;
  for (const auto& p : points_) {
    if ((p.head<2>() - c).squaredNorm() <= radius_m * radius_m) out.push_back(p);
  }
  return out;
}

Points2d samplePath(const Points2d& waypoints, double step_m) {
  Points2d out;
  if (waypoints.empty()) return out;
  out.push_back(waypoints.front());
  double carry = 0.0;
  for (size_t i = 1; i < waypoints.size(); ++i) {
    const Vector2d a = waypoints[i - 1], b = waypoints[i];
    const double len = (b - a).norm();
    double s = step_m - carry;
    while (s <= len) {
      out.push_back(a + (b - a) * (s / len));
      s += step_m;
    }
    carry = len - (s - step_m);
  }
  return out;
}

Scenario makeScenario(const FloorPlan& plan, const std::vector<Box>& solids,
                      const Vector2d& bounds_min, const Vector2d& bounds_max, const Sim2& T,
                      const Points2d& waypoints_sketch_m, double sketch_spacing_m, double d_gap_m,
                      double path_step_m) {
  Scenario sc;
  sc.sketch_plan = plan;
  sc.sketch_points_m = samplePlan(plan, sketch_spacing_m);
  const TraversabilityCheck free(plan, solids, bounds_min, bounds_max, 0.5);
  sc.candidates_m = makeCandidateGrid(bounds_min + Vector2d(0.5, 0.5), bounds_max, d_gap_m,
                                      [&](const Vector2d& p) { return free(p); });
  sc.T_world_sketch = T;
  sc.world_plan = transformed(plan, T);
  Points2d world_waypoints;
  for (const auto& w : waypoints_sketch_m) world_waypoints.push_back(T.apply(w));
  sc.path_world_m = samplePath(world_waypoints, path_step_m);
  return sc;
}

}  // namespace efs::registration::synthetic
