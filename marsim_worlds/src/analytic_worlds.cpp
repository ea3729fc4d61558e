// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/analytic_worlds.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace efs::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Slab test: the parameter interval [t_in, t_out] of the ray inside the box; false if the ray's
/// line misses it.
bool slab(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
          double* t_in, double* t_out) {
  double lo = -kInf, hi = kInf;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (o[a] < box.min()[a] || o[a] > box.max()[a]) return false;
      continue;
    }
    const double inv = 1.0 / d[a];
    double t1 = (box.min()[a] - o[a]) * inv, t2 = (box.max()[a] - o[a]) * inv;
    if (t1 > t2) std::swap(t1, t2);
    lo = std::max(lo, t1);
    hi = std::min(hi, t2);
    if (lo > hi) return false;
  }
  *t_in = lo;
  *t_out = hi;
  return true;
}

double exteriorDistance(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& p) {
  const Eigen::Vector3d below = (box.min() - p).cwiseMax(0.0);
  const Eigen::Vector3d above = (p - box.max()).cwiseMax(0.0);
  return (below + above).norm();
}

}  // namespace

AnalyticBoxWorld::AnalyticBoxWorld(const Eigen::AlignedBox3d& room_world) : room_(room_world) {
  if (room_.isEmpty() || (room_.sizes().array() <= 0.0).any()) {
    throw std::invalid_argument("AnalyticBoxWorld: the room box is empty");
  }
}

void AnalyticBoxWorld::addSolidBox(const Eigen::AlignedBox3d& box_world) {
  if (box_world.isEmpty() || (box_world.sizes().array() <= 0.0).any()) {
    throw std::invalid_argument("AnalyticBoxWorld::addSolidBox: the box is empty");
  }
  boxes_.push_back(box_world);
}

double AnalyticBoxWorld::castRay(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                 double max_range_m) const {
  double best = kInf;
  double t_in, t_out;
  if (slab(room_, o, d, &t_in, &t_out)) {
    // Hollow room: entering from outside hits the outer face, from inside the far face.
    const double t = t_in > 0.0 ? t_in : t_out;
    if (t >= 0.0) best = t;
  }
  for (const auto& b : boxes_) {
    if (!slab(b, o, d, &t_in, &t_out) || t_out < 0.0) continue;
    best = std::min(best, std::max(t_in, 0.0));
  }
  return best <= max_range_m ? best : kInf;
}

void AnalyticBoxWorld::castRays(const Eigen::Vector3d& origin_m,
                                const std::vector<Eigen::Vector3f>& dirs_unit, double max_range_m,
                                std::vector<float>* ranges_m) const {
  ranges_m->resize(dirs_unit.size());
  for (std::size_t i = 0; i < dirs_unit.size(); ++i) {
    const double r = castRay(origin_m, dirs_unit[i].cast<double>(), max_range_m);
    (*ranges_m)[i] = std::isfinite(r) ? static_cast<float>(r) : kNoHit;
  }
}

bool AnalyticBoxWorld::collides(const Eigen::Vector3d& p_m, double radius_m) const {
  if (!p_m.allFinite()) return true;
  for (int a = 0; a < 3; ++a) {
    if (p_m[a] - room_.min()[a] < radius_m || room_.max()[a] - p_m[a] < radius_m) return true;
  }
  for (const auto& b : boxes_) {
    if (exteriorDistance(b, p_m) < radius_m) return true;
  }
  return false;
}

double AnalyticBoxWorld::distanceToSurface(const Eigen::Vector3d& p_m) const {
  double d;
  if (room_.contains(p_m)) {
    d = std::min((p_m - room_.min()).minCoeff(), (room_.max() - p_m).minCoeff());
  } else {
    d = exteriorDistance(room_, p_m);
  }
  for (const auto& b : boxes_) d = std::min(d, exteriorDistance(b, p_m));
  return d;
}

AnalyticBoxWorld makeBoxRoom(const Eigen::Vector3d& size_m) {
  const Eigen::Vector3d lo(-0.5 * size_m.x(), -0.5 * size_m.y(), 0.0);
  return AnalyticBoxWorld(Eigen::AlignedBox3d(lo, lo + size_m));
}

AnalyticBoxWorld makeRoomWithPillar(const Eigen::Vector3d& size_m, double pillar_x_m,
                                    double pillar_y_m, double pillar_side_m) {
  AnalyticBoxWorld w = makeBoxRoom(size_m);
  const double h = 0.5 * pillar_side_m;
  w.addSolidBox(Eigen::AlignedBox3d(Eigen::Vector3d(pillar_x_m - h, pillar_y_m - h, 0.0),
                                    Eigen::Vector3d(pillar_x_m + h, pillar_y_m + h, size_m.z())));
  return w;
}

AnalyticBoxWorld makePillarHall(const Eigen::Vector3d& size_m, double spacing_m,
                                double pillar_side_m) {
  if (!(spacing_m > pillar_side_m) || !(pillar_side_m > 0.0)) {
    throw std::invalid_argument("makePillarHall: need spacing_m > pillar_side_m > 0");
  }
  AnalyticBoxWorld w = makeBoxRoom(size_m);
  const double h = 0.5 * pillar_side_m;
  const Eigen::AlignedBox3d& room = w.room();
  for (double x = room.min().x() + spacing_m; x <= room.max().x() - 0.5 * spacing_m;
       x += spacing_m) {
    for (double y = room.min().y() + spacing_m; y <= room.max().y() - 0.5 * spacing_m;
         y += spacing_m) {
      w.addSolidBox(Eigen::AlignedBox3d(Eigen::Vector3d(x - h, y - h, 0.0),
                                        Eigen::Vector3d(x + h, y + h, size_m.z())));
    }
  }
  return w;
}

}  // namespace efs::sim
