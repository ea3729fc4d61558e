// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// minco_traj benchmark: MINCO spatio-temporal optimisation time for 5..10 pieces (target: median
// < 5 ms) and safe-flight-corridor generation for a 30 m path (target: < 5 ms), on seeded random
// pillar fields. Prints tables; never asserts times. Times are thread CPU time in ms.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <vector>

#include "minco_traj/astar.h"
#include "minco_traj/corridor.h"
#include "minco_traj/local_grid.h"
#include "minco_traj/traj_optimizer.h"

using namespace efs::traj;
namespace {

// Thread CPU time: the machine running CI is shared, and wall time then measures the neighbours.
struct Clock {
  using time_point = double;
  static double now() {
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
  }
};
double ms(double a, double b) { return b - a; }
double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

double segDist(const std::vector<Eigen::Vector3d>& path, const Eigen::Vector3d& p) {
  double d = 1e9;
  for (size_t k = 0; k + 1 < path.size(); ++k) {
    const Eigen::Vector3d a = path[k], b = path[k + 1];
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    d = std::min(d, (a + t * (b - a) - p).norm());
  }
  return d;
}

// Pillars (vertical columns of points, 0.1 m spacing) kept `clear` away from the path.
std::vector<Eigen::Vector3d> pillarField(const std::vector<Eigen::Vector3d>& path, double clear,
                                         std::mt19937& rng) {
  Eigen::Vector3d lo = path[0], hi = path[0];
  for (const auto& p : path) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo.array() -= 3.0;
  hi.array() += 3.0;
  std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y());
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 400; ++i) {
    const double cx = ux(rng), cy = uy(rng);
    for (double dx = -0.2; dx <= 0.2; dx += 0.1)
      for (double dy = -0.2; dy <= 0.2; dy += 0.1)
        for (double z = 0.0; z <= 3.0; z += 0.1) {
          const Eigen::Vector3d p(cx + dx, cy + dy, z);
          if (segDist(path, p) > clear) pts.push_back(p);
        }
  }
  for (double x = lo.x(); x <= hi.x(); x += 0.1)  // floor and ceiling
    for (double y = lo.y(); y <= hi.y(); y += 0.1) {
      pts.emplace_back(x, y, -0.05);
      pts.emplace_back(x, y, 3.05);
    }
  return pts;
}

// A Livox-sized scan (20k returns) of the walls of a 20 x 12 x 4 m hall.
std::vector<Eigen::Vector3d> hallScan(const Eigen::Vector3d& sensor, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Vector3d half(10.0, 6.0, 2.0);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(u(rng), u(rng), 0.3 * u(rng)).normalized();
    double t = 1e9;
    for (int a = 0; a < 3; ++a)
      if (std::abs(d[a]) > 1e-9)
        t = std::min(t, (half[a] - std::copysign(sensor[a], d[a])) / std::abs(d[a]));
    pts.push_back(sensor + t * d);
  }
  return pts;
}

// Local grid update per scan (the trajectory server's per-scan cost) and window recentring.
void scanInsertionTable(std::mt19937& rng) {
  std::printf(
      "\nLocal grid update per scan (20k returns, hall 20 x 12 x 4 m, window 24 x 24 x 6 m "
      "at 0.1 m)\n| ray_downsample [m] | rays/scan | insert median [ms] | recenter [ms] |\n"
      "|---|---|---|---|\n");
  for (double rds : {0.0, 0.3, 0.5}) {
    LocalGridConfig gc;
    gc.ray_downsample_m = rds;
    LocalGrid grid(gc, Eigen::Vector3d(0, 0, 1));
    std::vector<double> t_ms;
    for (int k = 0; k < 6; ++k) {
      const Eigen::Vector3d sensor(0.3 * k, 0.0, 1.0);
      const auto scan = hallScan(sensor, rng);
      const auto t0 = Clock::now();
      grid.insertScan(sensor, scan);
      t_ms.push_back(ms(t0, Clock::now()));
    }
    std::vector<Eigen::Vector3i> bins;
    const auto scan = hallScan(Eigen::Vector3d(0, 0, 1), rng);
    for (const auto& p : scan)
      bins.push_back(rds > 0 ? (p / rds).array().floor().cast<int>().matrix()
                             : Eigen::Vector3i(static_cast<int>(bins.size()), 0, 0));
    std::sort(bins.begin(), bins.end(), [](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    });
    const size_t rays = std::unique(bins.begin(), bins.end()) - bins.begin();
    const auto r0 = Clock::now();
    grid.recenter(Eigen::Vector3d(2.5, 0.0, 1.0));
    const double rec = ms(r0, Clock::now());
    std::printf("| %.1f | %zu | %.1f | %.1f |\n", rds, rays, percentile(t_ms, 0.5), rec);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::mt19937 rng(7);
  // ---------------------------------------------------------------- optimisation
  std::printf(
      "MINCO spatio-temporal optimisation (v_max 4 m/s, a_max 6 m/s^2, 12 samples/piece)\n");
  std::printf(
      "| pieces | path [m] | median [ms] | p90 [ms] | iterations | evals | eval [us] | T [s] | "
      "v_max [m/s] | a_max [m/s^2] | feasible |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  TrajOptConfig ocfg;
  ocfg.max_piece_length_m = 100.0;  // one piece per polytope: pieces = seeds
  if (argc > 1) ocfg.lbfgs.rel_cost_tol = std::atof(argv[1]);
  if (argc > 2) ocfg.lbfgs.past = std::atoi(argv[2]);
  if (argc > 3) ocfg.samples_per_piece = std::atoi(argv[3]);
  TrajOptimizer opt(ocfg);
  CorridorConfig ccfg;
  ccfg.max_seed_length_m = 100.0;
  CorridorBuilder builder(ccfg);
  for (int n = 5; n <= 10; ++n) {
    std::vector<double> times;
    int iters = 0, evals = 0, feasible = 0, runs = 0;
    double dur = 0, vmax = 0, amax = 0, len = 0, eval_us = 0;
    for (int scene = 0; scene < 5; ++scene) {
      std::vector<Eigen::Vector3d> path = {{0, 0, 1.5}};
      std::uniform_real_distribution<double> turn(-0.9, 0.9), seg(2.5, 4.0), dz(-0.3, 0.3);
      double heading = 0;
      for (int k = 0; k < n; ++k) {
        heading += turn(rng);
        const double L = seg(rng);
        Eigen::Vector3d next =
            path.back() + Eigen::Vector3d(L * std::cos(heading), L * std::sin(heading), dz(rng));
        next.z() = std::clamp(next.z(), 0.8, 2.2);
        path.push_back(next);
      }
      const auto obstacles = pillarField(path, 0.6, rng);
      const auto corridor = builder.build(path, obstacles, Eigen::Vector3d(-100, -100, -1),
                                          Eigen::Vector3d(100, 100, 4));
      if (!corridor.ok() || static_cast<int>(corridor.polytopes.size()) != n) continue;
      Eigen::Matrix3d head = Eigen::Matrix3d::Zero(), tail = Eigen::Matrix3d::Zero();
      head.col(0) = path.front();
      tail.col(0) = path.back();
      if (scene == 0) {  // cost of one evaluation (MINCO solve, penalties, adjoint)
        const auto probe = opt.optimize(head, tail, corridor.polytopes);
        MincoCorridorCost cost(ocfg, head, tail, corridor.polytopes, probe.piece_polytope);
        Eigen::Matrix3Xd q(3, n - 1);
        Eigen::VectorXd T(n);
        for (int k = 0; k < n - 1; ++k) q.col(k) = path[k + 1];
        T.setConstant(1.0);
        Eigen::VectorXd x = cost.pack(q, T), g;
        const auto e0 = Clock::now();
        for (int k = 0; k < 2000; ++k) cost(x, g);
        eval_us = ms(e0, Clock::now()) * 1000.0 / 2000;
      }
      for (int rep = 0; rep < 5; ++rep) {
        const auto t0 = Clock::now();
        const auto res = opt.optimize(head, tail, corridor.polytopes);
        const auto t1 = Clock::now();
        times.push_back(ms(t0, t1));
        if (rep == 0) {
          ++runs;
          iters += res.solver.iterations;
          evals += res.solver.evaluations;
          feasible += res.ok();
          if (res.ok()) {
            dur += res.trajectory.duration();
            vmax = std::max(vmax, res.feasibility.max_speed_mps);
            amax = std::max(amax, res.feasibility.max_acceleration_mps2);
          }
          for (size_t k = 0; k + 1 < path.size(); ++k) len += (path[k + 1] - path[k]).norm();
        }
      }
    }
    if (runs == 0) continue;
    std::printf("| %d | %.1f | %.2f | %.2f | %.0f | %.0f | %.1f | %.2f | %.2f | %.2f | %d/%d |\n",
                n, len / runs, percentile(times, 0.5), percentile(times, 0.9), double(iters) / runs,
                double(evals) / runs, eval_us, feasible ? dur / feasible : 0.0, vmax, amax,
                feasible, runs);
  }

  // ---------------------------------------------------------------- corridor, 30 m path
  std::printf(
      "\nSafe flight corridor for a 30 m path through a pillar field (grid 0.1 m, inflation 0.3 "
      "m)\n");
  std::printf(
      "| scene | A* path [m] | seeds | A* [ms] | corridor [ms] | planes/poly | optimise [ms] | "
      "pieces | feasible |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  LocalGridConfig gcfg;
  gcfg.size_x_m = 36;
  gcfg.size_y_m = 16;
  gcfg.size_z_m = 4;
  std::vector<double> corridor_ms;
  for (int scene = 0; scene < 5; ++scene) {
    LocalGrid grid(gcfg, Eigen::Vector3d(15, 0, 1.5));
    grid.setAllFree();
    std::uniform_real_distribution<double> ux(2, 28), uy(-7, 7);
    for (int i = 0; i < 120; ++i) {
      const double cx = ux(rng), cy = uy(rng);
      for (double dx = -0.25; dx <= 0.25; dx += 0.1)
        for (double dy = -0.25; dy <= 0.25; dy += 0.1)
          for (double z = -0.45; z <= 3.5; z += 0.1) grid.setOccupied({cx + dx, cy + dy, z});
    }
    for (double x = -3; x <= 33; x += 0.1)
      for (double y = -8; y <= 8; y += 0.1) {
        grid.setOccupied({x, y, -0.45});
        grid.setOccupied({x, y, 3.45});
      }
    const Eigen::Vector3d s(0, 0, 1.5), g(30, 0.5, 1.5);
    grid.setFree(s);
    grid.setFree(g);
    AStarPlanner planner;
    const auto t0 = Clock::now();
    const auto astar = planner.plan(grid, s, g);
    const auto t1 = Clock::now();
    AStarConfig weighted;
    weighted.heuristic_weight = 1.5;
    AStarPlanner wplanner(weighted);
    wplanner.plan(grid, s, g);  // warm the scratch arrays
    const auto w0 = Clock::now();
    const auto wres = wplanner.plan(grid, s, g);
    const double w_ms = ms(w0, Clock::now());
    if (!astar.ok()) {
      std::printf("| %d | A* failed: %s |\n", scene, toString(astar.status));
      continue;
    }
    CorridorBuilder cb;  // defaults: seeds <= 4 m, 2 iterations, clearance 0.3 m
    CorridorResult corr;
    std::vector<double> ct;
    for (int rep = 0; rep < 5; ++rep) {
      const auto c0 = Clock::now();
      corr = cb.build(astar.path_world_m, grid);
      ct.push_back(ms(c0, Clock::now()));
    }
    const double cmed = percentile(ct, 0.5);
    {
      const auto g0 = Clock::now();
      std::vector<Eigen::Vector3d> tmp;
      size_t total = 0;
      for (const auto& [a, b] : cb.seeds(astar.path_world_m)) {
        tmp.clear();
        grid.occupiedCentersInBox(a.cwiseMin(b).array() - 1.3, a.cwiseMax(b).array() + 1.3, tmp,
                                  true);
        total += tmp.size();
      }
      std::printf(
          "  scene %d: occupied-cell gather %.2f ms (%zu points); A* %d expansions; weighted A* "
          "(1.5) %.2f ms, %d expansions, length %.1f m\n",
          scene, ms(g0, Clock::now()), total, astar.expansions, w_ms, wres.expansions,
          wres.grid_path_length_m);
    }
    corridor_ms.push_back(cmed);
    double planes = 0;
    for (const auto& p : corr.polytopes) planes += p.planeCount();
    Eigen::Matrix3d head = Eigen::Matrix3d::Zero(), tail = Eigen::Matrix3d::Zero();
    head.col(0) = s;
    tail.col(0) = astar.path_world_m.back();
    const auto o0 = Clock::now();
    const auto res = TrajOptimizer().optimize(head, tail, corr.polytopes);
    const auto o1 = Clock::now();
    double len = 0;
    for (size_t k = 0; k + 1 < astar.path_world_m.size(); ++k)
      len += (astar.path_world_m[k + 1] - astar.path_world_m[k]).norm();
    std::printf("| %d | %.1f | %zu | %.2f | %.2f | %.1f | %.2f | %zu | %s |\n", scene, len,
                corr.polytopes.size(), ms(t0, t1), cmed,
                planes / std::max<size_t>(1, corr.polytopes.size()), ms(o0, o1),
                res.piece_polytope.size(), res.ok() ? "yes" : res.message.c_str());
  }
  if (!corridor_ms.empty())
    std::printf("\ncorridor median over scenes: %.2f ms (target < 5 ms)\n",
                percentile(corridor_ms, 0.5));
  scanInsertionTable(rng);
  return 0;
}
