// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Observation map / occupancy / frontier / viewpoint / path-length timing and memory on a
// synthetic cave, one core.
//  - Scene: a winding tube (centre line of 5 m segments meandering in x-y and z, radius
//    3.5-5 m with bumps), ray cast by sphere tracing in this file.
//  - Scans: Livox Mid-360 shaped, 20k points per 10 Hz frame (360 deg azimuth, -7..+52 deg
//    elevation, low-discrepancy pattern shifted every frame), mounted with 15 deg pitch, 40 m
//    range, the vehicle flying along the centre line looking ahead (`step_m` per frame).
//  - Timed per frame: occupancy ray casting, observation-map update (targets: both together
//    under 20 ms median), frontier clustering + viewpoint update; at the end L(robot, viewpoint)
//    searches (cold), the same queries again (cache), and all of them by one Dijkstra
//    (PathSearch::lengthsFrom, as ExplorationManager plans); then passes over the whole map
//    (the openings search, one cell lookup per known cell); and the openings as plans ask for
//    them along the flight, by such a pass and from the cells an OpeningCellIndex keeps.
//  - Times are this thread's CPU time (one core), so other load on the machine does not count.
//  - Memory: map bytes per metre of cave and per m^2 of surface, every `report_every_m`.
//  - `manager`: ExplorationManager::update() time when it replans, per mode, along the cave.
// Usage: observation_map_bench [cave_length_m=150] [step_m=0.5] [report_every_m=25]
//        observation_map_bench manager [cave_length_m=150]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "efs_common/resource_usage.h"
#include "prior_guided_planner/exploration_manager.h"
#include "prior_guided_planner/frontier_clusters.h"
#include "prior_guided_planner/known_columns.h"
#include "prior_guided_planner/observation_map.h"
#include "prior_guided_planner/occupancy_map.h"
#include "prior_guided_planner/opening_cells.h"
#include "prior_guided_planner/openings.h"
#include "prior_guided_planner/path_length.h"
#include "prior_guided_planner/viewpoint_sampler.h"

using namespace efs::planner;

namespace {

constexpr double kPi = 3.14159265358979323846;

class Cave {
 public:
  explicit Cave(double length_m) {
    const int n = static_cast<int>(std::ceil(length_m / 5.0)) + 3;
    for (int k = -2; k < n; ++k) {
      const double x = 5.0 * k;
      centre_.emplace_back(x, 15.0 * std::sin(x / 40.0) + 4.0 * std::sin(x / 11.0),
                           2.0 * std::sin(x / 25.0));
    }
  }
  // Wall radius at a point: smooth bumps, 3.5..5 m.
  static double radius(const Eigen::Vector3d& p) {
    return 4.25 + 0.45 * std::sin(0.7 * p.x()) * std::sin(0.9 * p.y()) +
           0.3 * std::sin(1.3 * p.z() + 0.4 * p.x());
  }
  // Distance to the centre line near segment `seg` (updates seg to the closest one).
  double lineDistance(const Eigen::Vector3d& p, int& seg) const {
    double best = 1e300;
    int best_s = seg;
    const int lo = std::max(0, seg - 3), hi = std::min<int>(centre_.size() - 2, seg + 3);
    for (int s = lo; s <= hi; ++s) {
      const Eigen::Vector3d a = centre_[s], d = centre_[s + 1] - a;
      const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      const double dist = (a + t * d - p).norm();
      if (dist < best) best = dist, best_s = s;
    }
    seg = best_s;
    return best;
  }
  // Sphere tracing of the tube's inside: the wall is where the distance reaches the radius.
  bool cast(const Eigen::Vector3d& o, const Eigen::Vector3d& dir, int seg, double max_range_m,
            Eigen::Vector3d* hit) const {
    double t = 0.0;
    for (int it = 0; it < 200 && t < max_range_m; ++it) {
      const Eigen::Vector3d p = o + t * dir;
      const double gap = radius(p) - lineDistance(p, seg);
      if (gap < 0.01) {
        *hit = p;
        return true;
      }
      t += std::max(0.6 * gap, 0.01);
    }
    return false;
  }
  Eigen::Vector3d along(double s_m, Eigen::Vector3d* tangent, int* seg) const {
    const int k = std::min<int>(static_cast<int>(s_m / 5.0) + 2, centre_.size() - 2);
    const double f = s_m / 5.0 + 2 - k;
    *tangent = (centre_[k + 1] - centre_[k]).normalized();
    *seg = k;
    return centre_[k] + f * (centre_[k + 1] - centre_[k]);
  }

 private:
  std::vector<Eigen::Vector3d> centre_;
};

// Mid-360-like frame: low-discrepancy directions, shifted by the frame index.
std::vector<Eigen::Vector3d> mid360Scan(const Cave& cave, const Eigen::Vector3d& o, double yaw,
                                        int seg, int frame, int n_points, double pitch_rad) {
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(n_points);
  const double s_lo = std::sin(-7.0 * kPi / 180.0), s_hi = std::sin(52.0 * kPi / 180.0);
  const double cp = std::cos(pitch_rad), sp = std::sin(pitch_rad);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const double shift1 = std::fmod(frame * 0.3819660113, 1.0),
               shift2 = std::fmod(frame * 0.1234567, 1.0);
  for (int i = 0; i < n_points; ++i) {
    const double u = std::fmod(i * 0.7548776662466927 + shift1, 1.0);
    const double v = std::fmod(i * 0.5698402909980532 + shift2, 1.0);
    const double az = 2.0 * kPi * u;
    const double el = std::asin(s_lo + v * (s_hi - s_lo));
    const Eigen::Vector3d ds(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                             std::sin(el));
    // sensor -> body (pitch about y, nose down positive) -> world (yaw)
    const Eigen::Vector3d db(cp * ds.x() + sp * ds.z(), ds.y(), -sp * ds.x() + cp * ds.z());
    const Eigen::Vector3d dw(cy * db.x() - sy * db.y(), sy * db.x() + cy * db.y(), db.z());
    Eigen::Vector3d hit;
    if (cave.cast(o, dw, seg, 40.0, &hit)) pts.push_back(hit);
  }
  return pts;
}

// This thread's CPU time: the "one core" budget, unaffected by other load on the machine.
class CpuWatch {
 public:
  CpuWatch() { restart(); }
  void restart() { start_ = now(); }
  double elapsedMs() const { return 1e3 * (now() - start_); }

 private:
  static double now() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
  }
  double start_ = 0.0;
};

struct Series {
  std::vector<double> v;
  double pct(double q) const {
    if (v.empty()) return 0.0;
    std::vector<double> s = v;
    std::sort(s.begin(), s.end());
    return s[std::min(s.size() - 1, static_cast<size_t>(q * (s.size() - 1) + 0.5))];
  }
  double max() const { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
};

// The exploration manager flown along the cave (it does not steer: the robot follows the
// centre line, as in the map table), planning every `plan_every` frames. Times one update()
// that replans (map update excluded: scans go in beforehand) per mode.
void managerTable(double length_m, double step_m, int plan_every) {
  Cave cave(length_m + 45.0);
  const double kPitch = 15.0 * kPi / 180.0;
  // Guidepoints every 15 m along the centre line (sketch = world), PRM = distance along it.
  GuidepointPrior prior;
  for (double s = 0.0; s <= length_m + 30.0; s += 15.0) {
    Eigen::Vector3d tangent;
    int seg = 0;
    prior.ids.push_back(static_cast<uint32_t>(prior.ids.size()));
    prior.positions_sketch_m.push_back(cave.along(s, &tangent, &seg).head<2>());
  }
  const int n = prior.size();
  prior.prm_distance_m = CostMatrix(n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) prior.prm_distance_m(i, j) = 15.0 * std::abs(i - j);
  struct Mode {
    const char* name;
    BaselineMode mode;
    int hypotheses;
  };
  std::printf(
      "\nExplorationManager::update() when it replans (map update excluded), cave %.0f m, a plan "
      "every %d frames, %d guidepoints\n\n",
      length_m, plan_every, n);
  std::printf(
      "| mode | hypotheses | plans | median ms | p90 ms | max ms | viewpoints (median) | "
      "target |\n|---|---|---|---|---|---|---|---|\n");
  for (const Mode& m : {Mode{"prior_free", BaselineMode::kPriorFree, 0},
                        Mode{"nearest_frontier", BaselineMode::kNearestFrontier, 0},
                        Mode{"proposed", BaselineMode::kProposed, 1},
                        Mode{"proposed", BaselineMode::kProposed, 3}}) {
    ExplorationManagerConfig c;
    c.planner.mode = m.mode;
    c.replan_period_s = 0.0;
    ExplorationManager mgr(c,
                           m.hypotheses > 0 ? std::optional<GuidepointPrior>(prior) : std::nullopt);
    std::vector<Hypothesis> hs;
    for (int k = 0; k < m.hypotheses; ++k)
      hs.push_back(
          {k, efs::Sim2(0.02 * k, 1.0 + 0.05 * k, Eigen::Vector2d(1.5 * k, -k)), 1.0 / (1 + k)});
    if (!hs.empty()) mgr.setHypotheses(hs);
    Series t_plan, n_vps;
    int frame = 0;
    for (double s = 0.0; s <= length_m + 1e-9; s += step_m, ++frame) {
      Eigen::Vector3d tangent;
      int seg = 0;
      const Eigen::Vector3d o = cave.along(s, &tangent, &seg);
      const double yaw = std::atan2(tangent.y(), tangent.x());
      std::vector<Eigen::Vector3f> pts;
      for (const Eigen::Vector3d& p : mid360Scan(cave, o, yaw, seg, frame, 20000, kPitch))
        pts.push_back(p.cast<float>());
      mgr.insertScan(o, pts);
      if (frame % plan_every != 0) continue;
      RobotPose robot;
      robot.position_world_m = o;
      robot.yaw_rad = yaw;
      CpuWatch w;
      const ExplorationTarget& t = mgr.update(0.1 * frame, robot);
      const double ms = w.elapsedMs();
      if (!t.replanned) continue;
      t_plan.v.push_back(ms);
      n_vps.v.push_back(static_cast<double>(mgr.viewpoints().size()));
    }
    std::printf("| %s | %d | %zu | %.1f | %.1f | %.1f | %.0f | < 50 ms |\n", m.name, m.hypotheses,
                t_plan.v.size(), t_plan.pct(0.5), t_plan.pct(0.9), t_plan.max(), n_vps.pct(0.5));
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  if (argc > 1 && std::string(argv[1]) == "manager") {
    managerTable(argc > 2 ? std::atof(argv[2]) : 150.0, 0.5, 5);
    return 0;
  }
  const double length_m = argc > 1 ? std::atof(argv[1]) : 150.0;
  const double step_m = argc > 2 ? std::atof(argv[2]) : 0.5;
  const double report_every_m = argc > 3 ? std::atof(argv[3]) : 25.0;
  const int kPoints = 20000;
  const double kPitch = 15.0 * kPi / 180.0;

  Cave cave(length_m + 45.0);
  OccupancyMap occ;
  ObservationMap obs;
  FrontierClusterer clusters;
  ViewpointManager viewpoints;
  PathLengthCache paths(occ);

  Series t_occ, t_obs, t_map, t_front, t_vp, pts_per_scan;
  std::printf(
      "observation_map_bench: cave %.0f m, %.2f m per frame, %d-point Mid-360 frames, "
      "40 m range, 0.3 m cells, CPU time of one core\n\n",
      length_m, step_m, kPoints);
  std::printf(
      "| flown m | surface cells | well observed | frontier | occ. blocks | map MiB | B / m cave "
      "| B / m^2 surface | clusters |\n|---|---|---|---|---|---|---|---|---|\n");
  // Openings as a plan asks for them (every 5th frame: a plan per 0.5 s at 10 Hz), by a pass over
  // the whole map and from the cells an OpeningCellIndex keeps (marked after every scan).
  OpeningCellIndex opening_index(occ, std::nullopt);
  // The columns a scan has reached (where the sketch's places are unseen), kept alike.
  KnownColumns known_columns(occ);
  Series t_mark, t_plan_pass, t_plan_kept, t_columns_kept, t_columns_pass;
  int openings_differ = 0, columns_differ = 0;
  int frame = 0;
  double next_report = report_every_m;
  Eigen::Vector3d robot = Eigen::Vector3d::Zero();
  for (double s = 0.0; s <= length_m + 1e-9; s += step_m, ++frame) {
    Eigen::Vector3d tangent;
    int seg = 0;
    const Eigen::Vector3d o = cave.along(s, &tangent, &seg);
    robot = o;
    const std::vector<Eigen::Vector3d> pts =
        mid360Scan(cave, o, std::atan2(tangent.y(), tangent.x()), seg, frame, kPoints, kPitch);
    pts_per_scan.v.push_back(pts.size());
    CpuWatch w;
    occ.insertScan(o, pts);
    const double a = w.elapsedMs();
    w.restart();
    opening_index.update();
    t_mark.v.push_back(w.elapsedMs());
    w.restart();
    known_columns.update();
    t_columns_kept.v.push_back(w.elapsedMs());
    if (frame % 5 == 0) {
      w.restart();
      const KnownColumns rebuilt(occ);
      t_columns_pass.v.push_back(w.elapsedMs());
      if (rebuilt.size() != known_columns.size()) ++columns_differ;
      w.restart();
      const std::vector<Opening> pass = findOpenings(occ, o, std::nullopt);
      t_plan_pass.v.push_back(w.elapsedMs());
      w.restart();
      const std::vector<Opening> kept = findOpenings(occ, opening_index.cells(), o);
      t_plan_kept.v.push_back(w.elapsedMs());
      bool differ = kept.size() != pass.size();
      for (size_t i = 0; i < std::min(kept.size(), pass.size()); ++i)
        differ |=
            kept[i].id != pass[i].id || kept[i].viewpoint_world_m != pass[i].viewpoint_world_m;
      openings_differ += differ;
    }
    w.restart();
    obs.insertScan(o, pts);
    const double b = w.elapsedMs();
    paths.sync();
    w.restart();
    clusters.update(obs);
    const double c = w.elapsedMs();
    w.restart();
    viewpoints.update(clusters, occ, obs.resolution());
    const double d = w.elapsedMs();
    t_occ.v.push_back(a);
    t_obs.v.push_back(b);
    t_map.v.push_back(a + b);
    t_front.v.push_back(c);
    t_vp.v.push_back(d);
    if (s + 1e-9 >= next_report) {
      next_report += report_every_m;
      const double bytes = static_cast<double>(occ.memoryBytes() + obs.memoryBytes());
      const double surf_m2 = obs.numSurfaceCells() * obs.resolution() * obs.resolution();
      std::printf("| %.0f | %zu | %zu | %zu | %zu | %.1f | %.0f | %.0f | %zu |\n", s,
                  obs.numSurfaceCells(), obs.numWellObserved(), obs.numFrontierCells(),
                  occ.numBlocks(), bytes / (1 << 20), bytes / std::max(s, 1.0),
                  bytes / std::max(surf_m2, 1.0), clusters.clusters().size());
    }
  }
  std::printf("\nper frame (%d frames, %.0f points median):\n\n", frame, pts_per_scan.pct(0.5));
  auto header = [] {
    std::printf("| stage | median ms | p90 ms | max ms | target |\n|---|---|---|---|---|\n");
  };
  header();
  auto row = [](const char* name, const Series& s, const char* target) {
    std::printf("| %s | %.2f | %.2f | %.2f | %s |\n", name, s.pct(0.5), s.pct(0.9), s.max(),
                target);
  };
  row("occupancy ray casting", t_occ, "");
  row("observation map", t_obs, "");
  row("map update (occupancy + obs.)", t_map, "< 20 ms");
  row("frontier clustering", t_front, "");
  row("viewpoint update", t_vp, "");
  Series t_fv;
  for (size_t i = 0; i < t_front.v.size(); ++i) t_fv.v.push_back(t_front.v[i] + t_vp.v[i]);
  row("frontier + viewpoint update", t_fv, "");

  // Path lengths from the final robot position to every viewpoint: cold, then cached.
  const std::vector<Viewpoint> vps = viewpoints.all();
  Series cold, warm;
  int reachable = 0;
  for (const Viewpoint& v : vps) {
    CpuWatch w;
    const auto l = paths.length(~0ull, robot, static_cast<uint64_t>(v.id), v.position_world_m);
    cold.v.push_back(w.elapsedMs());
    reachable += l.has_value();
  }
  for (const Viewpoint& v : vps) {
    CpuWatch w;
    paths.length(~0ull, robot, static_cast<uint64_t>(v.id), v.position_world_m);
    warm.v.push_back(w.elapsedMs());
  }
  // The same robot lengths with one Dijkstra (what ExplorationManager does each plan), on a
  // fresh search so that no traversability memo is reused.
  std::vector<Eigen::Vector3d> targets;
  for (const Viewpoint& v : vps) targets.push_back(v.position_world_m);
  PathSearch fresh(occ);
  CpuWatch one;
  int dijkstra_expansions = 0;
  const auto many = fresh.lengthsFrom(robot, targets, &dijkstra_expansions);
  const double one_ms = one.elapsedMs();
  int many_reachable = 0;
  double max_rel_diff = 0.0;
  for (size_t i = 0; i < vps.size(); ++i) {
    many_reachable += many[i].has_value();
    const auto l =
        paths.length(~0ull, robot, static_cast<uint64_t>(vps[i].id), vps[i].position_world_m);
    if (l && many[i]) max_rel_diff = std::max(max_rel_diff, std::abs(*many[i] - *l) / *l);
  }
  // All pairs among (at most) the 60 viewpoints nearest to the robot: a planning cycle's matrix.
  std::vector<Viewpoint> near = vps;
  std::sort(near.begin(), near.end(), [&](const Viewpoint& x, const Viewpoint& y) {
    return (x.position_world_m - robot).squaredNorm() < (y.position_world_m - robot).squaredNorm();
  });
  if (near.size() > 60) near.resize(60);
  Series pair_cold;
  int pairs_straight = 0, pairs_total = 0;
  CpuWatch whole;
  for (size_t i = 0; i < near.size(); ++i) {
    for (size_t j = i + 1; j < near.size(); ++j) {
      CpuWatch w;
      paths.length(near[i].id, near[i].position_world_m, near[j].id, near[j].position_world_m);
      pair_cold.v.push_back(w.elapsedMs());
      ++pairs_total;
      pairs_straight +=
          occ.segmentSafe(near[i].position_world_m, near[j].position_world_m, 0.4, false);
    }
  }
  const double whole_ms = whole.elapsedMs();
  std::printf("\npath lengths robot -> %zu viewpoints (%d reachable):\n\n", vps.size(), reachable);
  header();
  row("L(robot, viewpoint), searched", cold, "");
  row("L(robot, viewpoint), cached", warm, "");
  Series all_cold, all_one;
  all_cold.v.push_back(std::accumulate(cold.v.begin(), cold.v.end(), 0.0));
  all_one.v.push_back(one_ms);
  row("L(robot, all viewpoints), one A* each", all_cold, "");
  row("L(robot, all viewpoints), one Dijkstra", all_one, "");
  std::printf(
      "\none Dijkstra: %d expansions, %d reachable (A*: %d), largest length difference to A* "
      "%.1f %%\n",
      dijkstra_expansions, many_reachable, reachable, 100.0 * max_rel_diff);
  std::printf(
      "all %d pairs of the %zu nearest viewpoints (%d straight): %.0f ms in total "
      "(incl. a straight-line check per pair for this count)\n",
      pairs_total, near.size(), pairs_straight, whole_ms);
  std::printf("\n");
  header();
  row("L(viewpoint, viewpoint), searched", pair_cold, "");

  // Passes over the whole map, the cost of a plan that tours openings (every plan, once the
  // first one had no surface viewpoint): the openings search, and the cell lookups it is made
  // of (a block lookup per cell, as collision checks and line-of-sight tests do).
  Series t_open, t_lookup;
  size_t openings_found = 0, known_free = 0;
  for (int rep = 0; rep < 5; ++rep) {
    CpuWatch w;
    openings_found = findOpenings(occ, robot, std::nullopt).size();
    t_open.v.push_back(w.elapsedMs());
    w.restart();
    size_t free_cells = 0;
    occ.forEachKnownCell([&](const efs::VoxelKey& k, double, OccupancyState) {
      free_cells += occ.isFree({k.x + 1, k.y, k.z});
    });
    t_lookup.v.push_back(w.elapsedMs());
    known_free = free_cells;
  }
  std::printf("\nwhole-map passes (%zu known cells, %zu blocks; 5 repetitions):\n\n",
              occ.numKnownCells(), occ.numBlocks());
  header();
  row("openings search (findOpenings)", t_open, "");
  row("one state() lookup per known cell", t_lookup, "");
  std::printf("\n%zu openings; %zu known cells have a free +x neighbour\n", openings_found,
              known_free);
  std::printf("\nopenings per plan along the flight (every 5th frame, %zu plans):\n\n",
              t_plan_pass.v.size());
  header();
  row("marking a scan's changes (OpeningCellIndex::update)", t_mark, "");
  row("openings, pass over the whole map", t_plan_pass, "");
  row("openings, from the kept cells", t_plan_kept, "");
  std::printf("\nplans whose openings differ between the two: %d\n", openings_differ);
  std::printf("\nknown columns (KnownColumns, %zu at the end):\n\n", known_columns.size());
  header();
  row("keeping them per scan (KnownColumns::update)", t_columns_kept, "");
  row("a pass over the whole map, every 5th frame", t_columns_pass, "");
  std::printf("\nframes whose kept column count differs from the pass's: %d\n", columns_differ);
  std::printf("\npeak RSS %.1f MiB\n", efs::peakRssBytes() / double(1 << 20));
  return 0;
}
