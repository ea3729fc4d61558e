// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Registration compute on a synthetic garage-size floor (~190 x 150 m, ~20k candidates at
// d_gap = 1 m), on one core: Phase-1 precomputation time, then per-frame addFrame() time
// (median, p90, max) along a ~300 m walk with a frame every 10 m (0.2 Hz at 2 m/s), and the
// accuracy of the best hypothesis against the known transform (err_m: distance between where the
// best hypothesis and the truth put the robot's sketch position). Thread CPU time is printed
// beside wall time because the machine may be shared.
//   registration_bench [--frames N] [--seed S]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "efs_common/resource_usage.h"
#include "sketch_registration/sketch_registration.h"
#include "sketch_registration/synthetic_scene.h"

using efs::Sim2;
using efs::Stopwatch;
using Eigen::Vector2d;
namespace reg = efs::registration;
namespace syn = efs::registration::synthetic;

namespace {
/// CPU time of this thread [ms]: robust against other jobs sharing the machine.
double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * ts.tv_sec + 1e-6 * ts.tv_nsec;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}
}  // namespace

int main(int argc, char** argv) {
  int max_frames = 40;
  uint64_t seed = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--frames")
      max_frames = std::atoi(argv[i + 1]);
    else if (k == "--seed")
      seed = std::strtoull(argv[i + 1], nullptr, 10);
  }
  Vector2d lo, hi;
  std::vector<syn::Box> solids;
  const syn::FloorPlan plan = syn::makeGarageFloor(seed, &lo, &hi, &solids);
  const Sim2 T_true(0.6, 1.25, Vector2d(30.0, -12.0));
  const reg::Points2d waypoints = {{4, 4}, {116, 4}, {116, 92}, {52, 92}, {52, 140}, {180, 140}};
  Stopwatch sw;
  double cpu0 = threadCpuMs();
  const syn::Scenario sc = syn::makeScenario(plan, solids, lo, hi, T_true, waypoints);
  const double scene_s = sw.elapsedSeconds();

  reg::SketchRegistration::Config config;
  sw.restart();
  cpu0 = threadCpuMs();
  reg::SketchRegistration registration(config, sc.sketch_points_m, sc.candidates_m);
  const double precompute_s = sw.elapsedSeconds();
  const double precompute_cpu_s = 1e-3 * (threadCpuMs() - cpu0);

  syn::LocalMapSimulator::Config sim_config;
  sim_config.num_rays = 720;
  syn::LocalMapSimulator sim(sc.world_plan, sim_config);
  std::vector<double> frame_ms, frame_cpu_ms;
  std::vector<std::string> rows;
  int frames = 0;
  for (size_t i = 0; i < sc.path_world_m.size() && frames < max_frames; ++i) {
    sim.scanAt(sc.path_world_m[i]);
    if (i % 5 != 4) continue;
    const Vector2d p = sc.path_world_m[i];
    const reg::Points3d local_map = sim.localMap(p, 40.0);
    sw.restart();
    cpu0 = threadCpuMs();
    const reg::RegistrationResult& r =
        registration.addFrame(static_cast<double>(i), {p.x(), p.y(), 1.5}, local_map);
    const double ms = sw.elapsedMs();
    const double cpu_ms = threadCpuMs() - cpu0;
    frame_ms.push_back(ms);
    frame_cpu_ms.push_back(cpu_ms);
    ++frames;
    char line[256];
    // err_m: "-" while there is no hypothesis.
    char err[16] = "      -";
    if (!r.hypotheses.empty()) {
      std::snprintf(err, sizeof(err), "%7.2f",
                    (r.hypotheses[0].T_world_sketch.apply(T_true.inverse().apply(p)) - p).norm());
    }
    std::snprintf(line, sizeof(line),
                  "| %5d | %7.1f | %7.1f | %6zu | %5zu | %4zu | %4zu | %-22s | %s |", frames, ms,
                  cpu_ms, local_map.size(), r.last_frame.candidates.size(), r.last_frame.icp_runs,
                  r.hypotheses.size(), reg::toString(r.status), err);
    rows.push_back(line);
  }
  std::printf("# registration_bench: synthetic garage %.0f x %.0f m, seed %llu, one core\n",
              hi.x() - lo.x(), hi.y() - lo.y(), static_cast<unsigned long long>(seed));
  std::printf("| item | value |\n|---|---|\n");
  std::printf("| sketch boundary points | %zu |\n", sc.sketch_points_m.size());
  std::printf("| candidates (d_gap 1 m) | %zu (%zu with a usable descriptor) |\n",
              registration.database().size(), registration.database().validCount());
  std::printf("| scene generation [s] | %.2f |\n", scene_s);
  std::printf("| Phase-1 precomputation wall / CPU [s] | %.3f / %.3f |\n", precompute_s,
              precompute_cpu_s);
  std::printf("| frames | %zu |\n", frame_ms.size());
  std::printf("| per-frame addFrame median wall / CPU [ms] | %.1f / %.1f |\n",
              percentile(frame_ms, 0.5), percentile(frame_cpu_ms, 0.5));
  std::printf("| per-frame addFrame p90 wall / CPU [ms] | %.1f / %.1f |\n",
              percentile(frame_ms, 0.9), percentile(frame_cpu_ms, 0.9));
  std::printf("| per-frame addFrame max wall / CPU [ms] | %.1f / %.1f |\n",
              percentile(frame_ms, 1.0), percentile(frame_cpu_ms, 1.0));
  std::printf("| peak RSS [MB] | %.0f |\n\n", efs::peakRssBytes() / 1e6);
  std::printf(
      "| frame | wall ms | cpu ms | map pts | cands | icp runs | hyps | status | err_m |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& l : rows) std::printf("%s\n", l.c_str());
  return 0;
}
