// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/world_generators.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>
#include <vector>

#include "efs_common/angles.h"
#include "efs_common/config_check.h"
#include "efs_common/segment_distance.h"
#include "marsim_worlds/seeded_random.h"

namespace efs::sim {
namespace {

using Box2 = Eigen::AlignedBox2d;
using Box3 = Eigen::AlignedBox3d;

void requireSize(const Eigen::Vector3d& size_m) {
  for (int a = 0; a < 3; ++a) {
    requireInRange("size_m[" + std::to_string(a) + "]", size_m[a], 2.0, 5000.0);
  }
}

// ---------------------------------------------------------------------------------------------
// Caves

struct TunnelNode {
  Eigen::Vector3d p;
  double radius_m;
  std::vector<int> segments;
};

struct TunnelSegment {
  int a, b;
};

/// Coarse 2D bucket grid over segment ids for the "keep tunnels apart" test.
class SegmentBuckets {
 public:
  SegmentBuckets(const Eigen::Vector2d& size_m, double cell_m)
      : cell_m_(cell_m),
        nx_(static_cast<int>(std::ceil(size_m.x() / cell_m)) + 1),
        ny_(static_cast<int>(std::ceil(size_m.y() / cell_m)) + 1),
        cells_(static_cast<size_t>(nx_) * ny_) {}

  void insert(int id, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    forCells(a.cwiseMin(b), a.cwiseMax(b), [&](std::vector<int>& c) { c.push_back(id); });
  }
  /// Segment ids whose bucket lies within `r` of `p` (a superset of the segments within `r`).
  std::vector<int> near(const Eigen::Vector2d& p, double r) {
    std::vector<int> out;
    const Eigen::Vector2d d(r, r);
    forCells(p - d, p + d, [&](std::vector<int>& c) { out.insert(out.end(), c.begin(), c.end()); });
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

 private:
  template <class F>
  void forCells(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, F&& f) {
    const int x0 = std::clamp(static_cast<int>(std::floor(lo.x() / cell_m_)), 0, nx_ - 1);
    const int x1 = std::clamp(static_cast<int>(std::floor(hi.x() / cell_m_)), 0, nx_ - 1);
    const int y0 = std::clamp(static_cast<int>(std::floor(lo.y() / cell_m_)), 0, ny_ - 1);
    const int y1 = std::clamp(static_cast<int>(std::floor(hi.y() / cell_m_)), 0, ny_ - 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) f(cells_[static_cast<size_t>(y) * nx_ + x]);
  }
  double cell_m_;
  int nx_, ny_;
  std::vector<std::vector<int>> cells_;
};

struct Tip {
  int node;
  double heading_rad;
  double pitch;  // dz/ds
  double remaining_m;
  bool trunk;
};

}  // namespace

std::string worldKindName(WorldKind kind) {
  switch (kind) {
    case WorldKind::kGarage:
      return "garage";
    case WorldKind::kSimpleCave:
      return "simple_cave";
    case WorldKind::kSubtCave:
      return "subt_cave";
    case WorldKind::kIndoor:
      return "indoor";
  }
  return "unknown";
}

WorldKind parseWorldKind(const std::string& name) {
  for (WorldKind k :
       {WorldKind::kGarage, WorldKind::kSimpleCave, WorldKind::kSubtCave, WorldKind::kIndoor}) {
    if (worldKindName(k) == name) return k;
  }
  throw std::invalid_argument("unknown world kind '" + name +
                              "' (expected garage, simple_cave, subt_cave or indoor)");
}

CaveConfig CaveConfig::subt(WorldSize size) {
  CaveConfig c;
  if (size == WorldSize::kSmall) {
    c.size_m = {48.0, 40.0, 12.0};
    c.tunnel_radius_m = 2.0;
    c.wall_roughness_m = 0.3;
    c.segment_length_m = 5.0;
    c.min_branch_length_m = 8.0;
    c.max_branch_length_m = 25.0;
    c.total_length_m = 160.0;
    c.branch_probability = 0.3;
  }
  return c;
}

CaveConfig CaveConfig::simple(WorldSize size) {
  CaveConfig c;
  c.size_m = {500.0, 50.0, 70.0};
  c.tunnel_radius_m = 4.5;
  c.radius_variation = 0.35;
  c.wall_roughness_m = 0.9;
  c.roughness_wavelength_m = 4.0;
  c.segment_length_m = 10.0;
  c.max_turn_rad = 0.35;
  c.max_slope = 0.35;
  c.trunk_heading_pull = 0.3;
  c.branch_probability = 0.06;
  c.min_branch_length_m = 20.0;
  c.max_branch_length_m = 60.0;
  c.total_length_m = 700.0;
  if (size == WorldSize::kSmall) {
    c.size_m = {48.0, 18.0, 20.0};
    c.tunnel_radius_m = 2.5;
    c.wall_roughness_m = 0.5;
    c.segment_length_m = 5.0;
    c.min_branch_length_m = 6.0;
    c.max_branch_length_m = 10.0;
    c.branch_probability = 0.15;
    c.total_length_m = 70.0;
  }
  return c;
}

void CaveConfig::validate() const {
  requireSize(size_m);
  requireInRange("resolution_m", resolution_m, 0.02, 2.0);
  requireInRange("tunnel_radius_m", tunnel_radius_m, 0.5, 50.0);
  requireInRange("radius_variation", radius_variation, 0.0, 0.8);
  requireInRange("vertical_squash", vertical_squash, 0.5, 3.0);
  requireInRange("wall_roughness_m", wall_roughness_m, 0.0, 0.5 * tunnel_radius_m);
  requireInRange("roughness_wavelength_m", roughness_wavelength_m, 0.2, 100.0);
  requireInRange("segment_length_m", segment_length_m, 0.5, 200.0);
  requireInRange("max_turn_rad", max_turn_rad, 0.0, M_PI);
  requireInRange("max_slope", max_slope, 0.0, 2.0);
  requireInRange("trunk_heading_pull", trunk_heading_pull, 0.0, 1.0);
  requireInRange("branch_probability", branch_probability, 0.0, 1.0);
  requirePositive("min_branch_length_m", min_branch_length_m);
  requireThat(max_branch_length_m >= min_branch_length_m, "max_branch_length_m",
              "must be >= min_branch_length_m");
  requireInRange("total_length_m", total_length_m, segment_length_m, 1e6);
  requireInRange("start_clearance_m", start_clearance_m, 0.0, tunnel_radius_m);
  const double margin = 2.0 * (tunnel_radius_m * (1.0 + radius_variation) + wall_roughness_m + 1.0);
  requireThat(size_m.x() > margin + segment_length_m && size_m.y() > margin, "size_m",
              "too small for tunnels of radius tunnel_radius_m");
  requireThat(size_m.z() * vertical_squash > margin, "size_m",
              "too low for tunnels of radius tunnel_radius_m");
}

VoxelWorld generateCave(const CaveConfig& c) {
  c.validate();
  SeededRandom rng(c.seed);
  const double r_max = c.tunnel_radius_m * (1.0 + c.radius_variation);
  const double margin_h = r_max + c.wall_roughness_m + 1.0;
  const double margin_v = (r_max + c.wall_roughness_m) / c.vertical_squash + 1.0;
  const Box2 inner(Eigen::Vector2d(margin_h, margin_h),
                   Eigen::Vector2d(c.size_m.x() - margin_h, c.size_m.y() - margin_h));
  const double z_lo = margin_v, z_hi = c.size_m.z() - margin_v;
  const double separation_m = 2.0 * (r_max + c.wall_roughness_m) + 1.0;

  auto radius = [&]() {
    return c.tunnel_radius_m * (1.0 + c.radius_variation * rng.uniform(-1.0, 1.0));
  };
  std::vector<TunnelNode> nodes;
  std::vector<TunnelSegment> segs;
  SegmentBuckets buckets(c.size_m.head<2>(), std::max(separation_m, c.segment_length_m));

  const Eigen::Vector3d start(margin_h + 0.5, c.size_m.y() * (0.5 + 0.2 * rng.uniform(-1.0, 1.0)),
                              0.5 * (z_lo + z_hi));
  nodes.push_back({start, c.tunnel_radius_m * (1.0 + c.radius_variation), {}});
  std::deque<Tip> tips;
  tips.push_back({0, 0.0, 0.0, 1.3 * c.size_m.x(), true});

  // Segments within two hops of `node` may legitimately be close to a new segment leaving it.
  auto nearbyInGraph = [&](int node) {
    std::vector<int> ids;
    for (int s : nodes[node].segments) {
      ids.push_back(s);
      const int other = segs[s].a == node ? segs[s].b : segs[s].a;
      ids.insert(ids.end(), nodes[other].segments.begin(), nodes[other].segments.end());
    }
    return ids;
  };
  auto farFromOthers = [&](const Eigen::Vector2d& q, const std::vector<int>& exempt) {
    for (int s : buckets.near(q, separation_m)) {
      if (std::find(exempt.begin(), exempt.end(), s) != exempt.end()) continue;
      if (distanceToSegment<2>(q, nodes[segs[s].a].p.head<2>(), nodes[segs[s].b].p.head<2>()) <
          separation_m) {
        return false;
      }
    }
    return true;
  };

  double total_m = 0.0;
  int respawns = 0;
  while (total_m < c.total_length_m) {
    if (tips.empty()) {
      // The network closed in on itself before the budget: sprout a new branch somewhere.
      if (++respawns > 400 || nodes.size() < 2) break;
      const int n = 1 + static_cast<int>(rng.index(nodes.size() - 1));
      tips.push_back({n, rng.uniform(-M_PI, M_PI), 0.0,
                      rng.uniform(c.min_branch_length_m, c.max_branch_length_m), false});
    }
    Tip tip = tips.front();
    tips.pop_front();
    const Eigen::Vector3d p = nodes[tip.node].p;
    const std::vector<int> exempt = nearbyInGraph(tip.node);
    bool placed = false;
    Eigen::Vector3d q;
    double heading = tip.heading_rad, pitch = tip.pitch, len = c.segment_length_m;
    for (int attempt = 0; attempt < 8 && !placed; ++attempt) {
      heading = tip.heading_rad + rng.uniform(-1.0, 1.0) * c.max_turn_rad * (1.0 + 0.5 * attempt);
      if (tip.trunk) heading -= c.trunk_heading_pull * wrapAngle(heading);
      pitch =
          std::clamp(tip.pitch + rng.uniform(-0.5, 0.5) * c.max_slope, -c.max_slope, c.max_slope);
      len = c.segment_length_m * rng.uniform(0.75, 1.25);
      q = p + len * Eigen::Vector3d(std::cos(heading), std::sin(heading), pitch);
      if (q.z() < z_lo || q.z() > z_hi) {
        pitch = -pitch;
        q.z() = std::clamp(q.z(), z_lo, z_hi);
      }
      if (!inner.contains(q.head<2>())) continue;
      if (!farFromOthers(q.head<2>(), exempt)) continue;
      if (!farFromOthers(0.5 * (p + q).head<2>(), exempt)) continue;
      placed = true;
    }
    if (!placed) continue;  // a dead end
    const int n = static_cast<int>(nodes.size());
    nodes.push_back({q, radius(), {}});
    const int s = static_cast<int>(segs.size());
    segs.push_back({tip.node, n});
    nodes[tip.node].segments.push_back(s);
    nodes[n].segments.push_back(s);
    buckets.insert(s, p.head<2>(), q.head<2>());
    total_m += (q - p).norm();
    if (tip.remaining_m - len > 0.0) {
      tips.push_back({n, heading, pitch, tip.remaining_m - len, tip.trunk});
    }
    if (rng.chance(c.branch_probability)) {
      const double side = rng.chance(0.5) ? 1.0 : -1.0;
      tips.push_back({n, heading + side * rng.uniform(0.7, 1.7), 0.0,
                      rng.uniform(c.min_branch_length_m, c.max_branch_length_m), false});
    }
  }

  VoxelWorld world(Box3(Eigen::Vector3d::Zero(), c.size_m), c.resolution_m,
                   VoxelWorld::Fill::kSolid);
  const ValueNoise noise(c.seed ^ 0x5EEDC0FFEEULL, c.roughness_wavelength_m, 2);
  // 2 octaves of smoothstep value noise in [-1, 1]: gradient norm < 8 / wavelength.
  const double noise_lipschitz = c.wall_roughness_m * 8.0 / c.roughness_wavelength_m;
  const Eigen::Vector3d squash(1.0, 1.0, c.vertical_squash);
  for (const TunnelSegment& s : segs) {
    const TunnelNode& na = nodes[s.a];
    const TunnelNode& nb = nodes[s.b];
    const Eigen::Vector3d a = na.p.cwiseProduct(squash), b = nb.p.cwiseProduct(squash);
    const Eigen::Vector3d ab = b - a;
    const double len2 = std::max(ab.squaredNorm(), 1e-12);
    const double r_seg = std::max(na.radius_m, nb.radius_m) + c.wall_roughness_m;
    const Eigen::Vector3d reach(r_seg, r_seg, r_seg / c.vertical_squash);
    Box3 box(na.p.cwiseMin(nb.p) - reach, na.p.cwiseMax(nb.p) + reach);
    const double lipschitz =
        c.vertical_squash * (1.0 + std::abs(nb.radius_m - na.radius_m) / std::sqrt(len2)) +
        noise_lipschitz;
    world.paint(box, false, lipschitz, [&](const Eigen::Vector3d& p_m) {
      const Eigen::Vector3d ps = p_m.cwiseProduct(squash);
      const double t = std::clamp((ps - a).dot(ab) / len2, 0.0, 1.0);
      const double r = na.radius_m + t * (nb.radius_m - na.radius_m);
      return (a + t * ab - ps).norm() - r + c.wall_roughness_m * noise(p_m);
    });
  }
  world.compact();
  world.name = "cave";
  world.sketch_band = {0.0, c.size_m.z()};
  // Start at the trunk's first node, looking down the tunnel; fall back along the trunk if the
  // wall noise left too little room.
  for (size_t i = 0; i < std::min<size_t>(nodes.size(), 20); ++i) {
    const Eigen::Vector3d& p = nodes[i].p;
    if (!world.collides(p, c.start_clearance_m) && !world.occupiedAt(p)) {
      world.start_poses = {{p, 0.0}};
      break;
    }
  }
  world.validateStartPoses(c.start_clearance_m);
  return world;
}

// ---------------------------------------------------------------------------------------------
// Garage

GarageConfig GarageConfig::preset(WorldSize size) {
  GarageConfig c;
  if (size == WorldSize::kSmall) {
    c.size_m = {40.0, 34.0, 4.0};
    c.cross_aisle_spacing_m = 24.0;
    c.service_cores = 1;
  }
  return c;
}

void GarageConfig::validate() const {
  requireSize(size_m);
  requireInRange("resolution_m", resolution_m, 0.02, 2.0);
  requireInRange("wall_thickness_m", wall_thickness_m, resolution_m, 5.0);
  requireInRange("bay_width_m", bay_width_m, 1.5, 10.0);
  requireInRange("bay_depth_m", bay_depth_m, 3.0, 10.0);
  requireInRange("aisle_width_m", aisle_width_m, 2.0, 20.0);
  requireInRange("pillar_size_m", pillar_size_m, 0.0, 3.0);
  requireInRange("bays_per_pillar", bays_per_pillar, 1, 20);
  requireInRange("cross_aisle_spacing_m", cross_aisle_spacing_m, 2.0 * aisle_width_m, 1e4);
  requireInRange("car_probability", car_probability, 0.0, 1.0);
  requireInRange("service_cores", service_cores, 0, 100);
  requireInRange("start_clearance_m", start_clearance_m, 0.0, 0.5 * aisle_width_m);
  requireThat(
      size_m.x() > 3.0 * aisle_width_m && size_m.y() > 2.0 * aisle_width_m + 2.0 * bay_depth_m,
      "size_m", "too small for one parking module");
  requireThat(size_m.z() > 2.5, "size_m", "ceiling lower than 2.5 m");
}

VoxelWorld generateGarage(const GarageConfig& c) {
  c.validate();
  SeededRandom rng(c.seed);
  const double t = c.wall_thickness_m, h = c.size_m.z();
  const Eigen::Vector3d lo(-t, -t, -t), hi = c.size_m + Eigen::Vector3d(t, t, t);
  VoxelWorld world(alignBrickBoundary(Box3(lo, hi), h, c.resolution_m), c.resolution_m,
                   VoxelWorld::Fill::kSolid);
  world.fillBox(Box3(Eigen::Vector3d::Zero(), c.size_m), false);
  world.setExplorationBox(Box3(Eigen::Vector3d::Zero(), c.size_m));
  auto solid = [&](double x0, double y0, double x1, double y1, double z1) {
    world.fillBox(Box3(Eigen::Vector3d(x0, y0, 0.0), Eigen::Vector3d(x1, y1, z1)), true);
  };

  const double a = c.aisle_width_m, d = c.bay_depth_m;
  // x ranges of bay runs between the perimeter aisles, split by cross aisles.
  std::vector<std::pair<double, double>> runs;
  for (double x = a; x < c.size_m.x() - a - c.bay_width_m;) {
    const double end = std::min(x + c.cross_aisle_spacing_m - a, c.size_m.x() - a);
    const double n_bays = std::floor((end - x) / c.bay_width_m);
    if (n_bays >= 1) runs.emplace_back(x, x + n_bays * c.bay_width_m);
    x = end + a;
  }
  // y of each double row of bays (back to back), separated by aisles.
  std::vector<double> rows;
  for (double y = a; y + 2.0 * d + a <= c.size_m.y() + 1e-9; y += 2.0 * d + a) rows.push_back(y);

  // Service cores replace a stretch of bays in a random double row.
  std::vector<Box2> cores;
  for (int i = 0; i < c.service_cores && !rows.empty() && !runs.empty(); ++i) {
    const double y = rows[rng.index(rows.size())];
    const auto& run = runs[rng.index(runs.size())];
    const double w = std::min(8.0, run.second - run.first);
    const double x = rng.uniform(run.first, run.second - w);
    cores.emplace_back(Eigen::Vector2d(x, y + 0.5), Eigen::Vector2d(x + w, y + 2.0 * d - 0.5));
    solid(x, y + 0.5, x + w, y + 2.0 * d - 0.5, h);
  }
  auto inCore = [&](const Eigen::Vector2d& p) {
    for (const Box2& b : cores)
      if (b.exteriorDistance(p) < 0.5) return true;
    return false;
  };

  const double ps = 0.5 * c.pillar_size_m;
  for (double y : rows) {
    const double spine = y + d;  // the line between back-to-back bays carries the pillars
    for (const auto& run : runs) {
      const int n_bays = static_cast<int>(std::lround((run.second - run.first) / c.bay_width_m));
      for (int k = 0; k <= n_bays; k += c.bays_per_pillar) {
        const double x = run.first + k * c.bay_width_m;
        if (ps > 0.0 && !inCore({x, spine})) solid(x - ps, spine - ps, x + ps, spine + ps, h);
      }
      for (int k = 0; k < n_bays; ++k) {
        for (int side = 0; side < 2; ++side) {
          if (!rng.chance(c.car_probability)) continue;
          const double cx = run.first + (k + 0.5) * c.bay_width_m + rng.uniform(-0.15, 0.15);
          const double len = rng.uniform(4.1, 4.8), wid = rng.uniform(1.7, 1.9);
          const double height = rng.uniform(1.35, 1.6);  // below the sketch band: not drawn
          const double back = side == 0 ? spine - 0.35 : spine + 0.35;
          const double front = side == 0 ? back - len : back + len;
          if (inCore({cx, 0.5 * (back + front)})) continue;
          solid(cx - 0.5 * wid, std::min(back, front), cx + 0.5 * wid, std::max(back, front),
                height);
        }
      }
    }
  }
  // Partition walls across the bay rows only (aisles stay open: high connectivity).
  const double wall_x = c.size_m.x() * rng.uniform(0.4, 0.6);
  for (double y : rows) solid(wall_x - 0.1, y + 0.3, wall_x + 0.1, y + 2.0 * d - 0.3, h);

  world.compact();
  world.name = "garage";
  world.sketch_band = {1.0, 1.8};
  world.start_poses = {
      {Eigen::Vector3d(0.5 * a, rng.uniform(0.3, 0.7) * c.size_m.y(), std::min(1.2, 0.5 * h)),
       0.0}};
  world.validateStartPoses(c.start_clearance_m);
  return world;
}

// ---------------------------------------------------------------------------------------------
// Indoor architecture

IndoorConfig IndoorConfig::preset(WorldSize size) {
  IndoorConfig c;
  if (size == WorldSize::kSmall) {
    c.size_m = {40.0, 30.0, 4.0};
    c.corridor_length_m = 55.0;
    c.max_corridor_segment_m = 18.0;
    c.room_attempts = 400;
  }
  return c;
}

void IndoorConfig::validate() const {
  requireSize(size_m);
  requireInRange("resolution_m", resolution_m, 0.02, 1.0);
  requireInRange("wall_thickness_m", wall_thickness_m, resolution_m, 2.0);
  requireInRange("corridor_width_m", corridor_width_m, 1.0, 10.0);
  requireInRange("min_corridor_segment_m", min_corridor_segment_m, corridor_width_m, 500.0);
  requireThat(max_corridor_segment_m >= min_corridor_segment_m, "max_corridor_segment_m",
              "must be >= min_corridor_segment_m");
  requireInRange("corridor_branch_probability", corridor_branch_probability, 0.0, 1.0);
  requireInRange("corridor_length_m", corridor_length_m, min_corridor_segment_m, 1e5);
  requireInRange("min_room_m", min_room_m, door_width_m + 2.0 * wall_thickness_m, 100.0);
  requireThat(max_room_m >= min_room_m, "max_room_m", "must be >= min_room_m");
  requireInRange("room_attempts", room_attempts, 0, 1000000);
  requireInRange("suite_probability", suite_probability, 0.0, 1.0);
  requireInRange("door_width_m", door_width_m, 0.5, 10.0);
  requireInRange("door_height_m", door_height_m, 1.0, size_m.z());
  requireInRange("start_clearance_m", start_clearance_m, 0.0, 0.5 * corridor_width_m);
  requireThat(size_m.x() > min_corridor_segment_m + 4.0 * wall_thickness_m &&
                  size_m.y() > min_corridor_segment_m + 4.0 * wall_thickness_m,
              "size_m", "too small for one corridor segment");
}

VoxelWorld generateIndoor(const IndoorConfig& c) {
  c.validate();
  SeededRandom rng(c.seed);
  const double t = c.wall_thickness_m, w = c.corridor_width_m;
  const Box2 site(Eigen::Vector2d(t, t), Eigen::Vector2d(c.size_m.x() - t, c.size_m.y() - t));
  std::vector<Box2> spaces;  // corridors then rooms: free rectangles
  std::vector<Box2> doors;
  std::vector<int> corridor_ids, room_ids;
  auto fits = [&](const Box2& b, int allowed_overlap) {
    if (!site.contains(b)) return false;
    // Grown by just under a wall: a neighbour exactly one wall away is allowed.
    const Eigen::Vector2d g = Eigen::Vector2d::Constant(t - 1e-6);
    const Box2 grown(b.min() - g, b.max() + g);
    for (size_t i = 0; i < spaces.size(); ++i) {
      if (static_cast<int>(i) == allowed_overlap) continue;
      if (!grown.intersection(spaces[i]).isEmpty()) return false;
    }
    return true;
  };
  static const Eigen::Vector2d kDirs[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  auto corridorBox = [&](const Eigen::Vector2d& p, int dir, double len) {
    const Eigen::Vector2d e = p + kDirs[dir] * len;
    const Eigen::Vector2d back = p - kDirs[dir] * 0.5 * w;  // overlap the corridor we leave
    const Eigen::Vector2d side =
        Eigen::Vector2d(kDirs[dir].y(), kDirs[dir].x()).cwiseAbs() * 0.5 * w;
    return Box2(back.cwiseMin(e) - side, back.cwiseMax(e) + side);
  };

  struct CorridorTip {
    Eigen::Vector2d p;
    int dir;
    int parent;
  };
  std::deque<CorridorTip> tips;
  const Eigen::Vector2d p0(c.size_m.x() * rng.uniform(0.3, 0.5),
                           c.size_m.y() * rng.uniform(0.3, 0.7));
  const int dir0 = static_cast<int>(rng.index(4));
  tips.push_back({p0, dir0, -1});
  double corridor_m = 0.0;
  while (!tips.empty() && corridor_m < c.corridor_length_m) {
    const size_t pick = rng.index(tips.size());
    const CorridorTip tip = tips[pick];
    tips.erase(tips.begin() + static_cast<long>(pick));
    double len = rng.uniform(c.min_corridor_segment_m, c.max_corridor_segment_m);
    Box2 box;
    bool ok = false;
    for (int attempt = 0; attempt < 3 && !ok; ++attempt, len *= 0.6) {
      if (len < c.min_corridor_segment_m * 0.5) break;
      box = corridorBox(tip.p, tip.dir, len);
      ok = fits(box, tip.parent);
    }
    if (!ok) continue;
    const int id = static_cast<int>(spaces.size());
    spaces.push_back(box);
    corridor_ids.push_back(id);
    corridor_m += len;
    const Eigen::Vector2d end = tip.p + kDirs[tip.dir] * len;
    const double turn = rng.uniform();
    const int next_dir = turn < 0.4 ? tip.dir : (tip.dir + (turn < 0.7 ? 1 : 3)) % 4;
    tips.push_back({end, next_dir, id});
    if (rng.chance(c.corridor_branch_probability)) {
      const Eigen::Vector2d mid = tip.p + kDirs[tip.dir] * len * rng.uniform(0.3, 0.8);
      tips.push_back({mid, (tip.dir + (rng.chance(0.5) ? 1 : 3)) % 4, id});
    }
  }
  if (spaces.empty()) throw std::runtime_error("indoor generator: no corridor fits in size_m");

  // Rooms against a host's side, the wall between them pierced by one door.
  for (int attempt = 0; attempt < c.room_attempts; ++attempt) {
    const bool suite = !room_ids.empty() && rng.chance(c.suite_probability);
    const int host =
        suite ? room_ids[rng.index(room_ids.size())] : corridor_ids[rng.index(corridor_ids.size())];
    const Box2& hb = spaces[static_cast<size_t>(host)];
    const int side = static_cast<int>(rng.index(4));
    const int along = side % 2 == 0 ? 1 : 0;  // sides 0/2 are x = const walls
    const int across = 1 - along;
    const double width = rng.uniform(c.min_room_m, c.max_room_m);
    const double depth = rng.uniform(c.min_room_m, c.max_room_m);
    const double centre = rng.uniform(hb.min()[along], hb.max()[along]);
    Eigen::Vector2d rmin, rmax;
    rmin[along] = centre - 0.5 * width;
    rmax[along] = centre + 0.5 * width;
    if (side < 2) {
      rmin[across] = hb.max()[across] + t;
      rmax[across] = rmin[across] + depth;
    } else {
      rmax[across] = hb.min()[across] - t;
      rmin[across] = rmax[across] - depth;
    }
    const Box2 room(rmin, rmax);
    // The shared stretch of wall must take a door with a wall stub either side.
    const double s_lo = std::max(rmin[along], hb.min()[along]) + t;
    const double s_hi = std::min(rmax[along], hb.max()[along]) - t;
    if (s_hi - s_lo < c.door_width_m) continue;
    if (!fits(room, -1)) continue;
    const double dc = rng.uniform(s_lo + 0.5 * c.door_width_m, s_hi - 0.5 * c.door_width_m);
    Eigen::Vector2d dmin, dmax;
    dmin[along] = dc - 0.5 * c.door_width_m;
    dmax[along] = dc + 0.5 * c.door_width_m;
    dmin[across] = side < 2 ? hb.max()[across] - 0.05 : rmax[across] - 0.05;
    dmax[across] = side < 2 ? rmin[across] + 0.05 : hb.min()[across] + 0.05;
    room_ids.push_back(static_cast<int>(spaces.size()));
    spaces.push_back(room);
    doors.emplace_back(dmin, dmax);
  }

  const double h = c.size_m.z();
  VoxelWorld world(alignBrickBoundary(Box3(Eigen::Vector3d(0, 0, -t),
                                           Eigen::Vector3d(c.size_m.x(), c.size_m.y(), h + t)),
                                      h, c.resolution_m),
                   c.resolution_m, VoxelWorld::Fill::kSolid);
  world.setExplorationBox(Box3(Eigen::Vector3d::Zero(), c.size_m));
  for (const Box2& b : spaces) {
    world.fillBox(Box3(Eigen::Vector3d(b.min().x(), b.min().y(), 0.0),
                       Eigen::Vector3d(b.max().x(), b.max().y(), h)),
                  false);
  }
  for (const Box2& b : doors) {
    world.fillBox(Box3(Eigen::Vector3d(b.min().x(), b.min().y(), 0.0),
                       Eigen::Vector3d(b.max().x(), b.max().y(), c.door_height_m)),
                  false);
  }
  world.compact();
  world.name = "indoor";
  world.sketch_band = {1.0, 1.8};
  const Box2& first = spaces[static_cast<size_t>(corridor_ids.front())];
  world.start_poses = {
      {Eigen::Vector3d(first.center().x(), first.center().y(), std::min(1.2, 0.5 * h)),
       dir0 * 0.5 * M_PI}};
  world.validateStartPoses(c.start_clearance_m);
  return world;
}

VoxelWorld generateWorld(WorldKind kind, WorldSize size, uint64_t seed, double resolution_m) {
  switch (kind) {
    case WorldKind::kGarage: {
      GarageConfig c = GarageConfig::preset(size);
      c.seed = seed;
      c.resolution_m = resolution_m;
      VoxelWorld w = generateGarage(c);
      return w;
    }
    case WorldKind::kIndoor: {
      IndoorConfig c = IndoorConfig::preset(size);
      c.seed = seed;
      c.resolution_m = resolution_m;
      return generateIndoor(c);
    }
    case WorldKind::kSimpleCave:
    case WorldKind::kSubtCave: {
      CaveConfig c =
          kind == WorldKind::kSimpleCave ? CaveConfig::simple(size) : CaveConfig::subt(size);
      c.seed = seed;
      c.resolution_m = resolution_m;
      VoxelWorld w = generateCave(c);
      w.name = worldKindName(kind);
      return w;
    }
  }
  throw std::invalid_argument("generateWorld: unknown kind");
}

}  // namespace efs::sim
