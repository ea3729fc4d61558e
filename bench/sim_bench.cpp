// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// sim_bench: real-time factor of the MARSIM-like simulator alone (dynamics at 500 Hz, Livox
// Mid-360 at its default 200k points/s ray cast against the world, registered scans, odometry,
// ground-truth coverage), stepped as fast as possible on one core. Target (issue 3): >= 20x real
// time on the generated garage and SubT-scale cave. The vehicle hovers and turns at 0.5 rad/s so
// that the scans sweep the surroundings; the analytic worlds (closed-form ray casts) show the
// simulator's own cost, the voxel worlds add the world's ray casting.
//
// Usage: sim_bench [--seconds 10] [--small] [--analytic-only] [--worlds garage,subt_cave]
#include <time.h>

#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "efs_common/cli_args.h"
#include "efs_common/resource_usage.h"
#include "marsim_worlds/analytic_worlds.h"
#include "marsim_worlds/simulator.h"

#if __has_include("marsim_worlds/world_generators.h")
#include "marsim_worlds/world_generators.h"
#define EFS_HAVE_WORLD_GENERATORS 1
#endif

namespace {

using namespace efs::sim;

/// CPU time of this thread: on a shared machine the wall clock also counts other processes.
double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Row {
  std::string world;
  double build_s = 0, world_mb = 0;
  std::size_t gt_voxels = 0;
  double sim_s = 0, wall_s = 0, cpu_s = 0, rtf = 0, rtf_wall = 0, mrays_per_s = 0,
         pts_per_frame = 0, coverage = 0;
  bool collided = false;
};

Row runOne(const std::string& name, const WorldGeometry& world, const Eigen::Vector3d& start,
           double start_yaw, double seconds, double build_s, double world_mb, bool with_avia) {
  Row row;
  row.world = name + (with_avia ? " (Avia)" : "");
  row.build_s = build_s;
  row.world_mb = world_mb;
  SimulatorConfig c;
  c.initial_position_m = start;
  c.initial_yaw_rad = start_yaw;
  c.lidar.range_noise_std_m = 0.02;
  c.odometry.position_noise_std_m = 0.01;
  c.odometry.position_drift_std_m_per_sqrt_s = 0.002;
  if (with_avia) c.lidar.pattern = LivoxPatternConfig::avia();
  Simulator sim(world, c);
  // Ground truth for coverage: the surface seen from free points within 20 m of the start
  // (a whole SubT-scale cave would take minutes to sample; the per-return cost is the same).
  ObservableSurfaceConfig oc;
  oc.rays_per_point = 20000;
  oc.max_range_m = c.lidar.max_range_m;
  const Eigen::AlignedBox3d local(start - Eigen::Vector3d(20, 20, 3),
                                  start + Eigen::Vector3d(20, 20, 3));
  const auto samples = freeSamplePoints(world, local.intersection(world.bounds()), 2.0, 0.5);
  sim.setCoverageGroundTruth(observableSurfaceKeys(world, samples, oc));
  row.gt_voxels = sim.coverage()->totalVoxels();

  AttitudeTargetCommand turn;
  turn.type_mask = AttitudeTargetCommand::kIgnoreAttitude;
  turn.body_rate_des_rad_s = Eigen::Vector3d(0, 0, 0.5);
  turn.thrust_normalized = c.quadrotor.hover_thrust_normalized;
  sim.setCommand(turn);

  std::size_t points = 0, frames = 0;
  uint64_t last_seq = 0;
  efs::Stopwatch watch;
  const double cpu0 = threadCpuSeconds();
  const double dt = 0.01;  // a 100 Hz caller (the ROS node's timer, a controller)
  for (int i = 0; i < static_cast<int>(seconds / dt + 0.5); ++i) {
    sim.step(dt);
    if (sim.latestScan().seq != last_seq) {
      last_seq = sim.latestScan().seq;
      points += sim.latestScan().points_world.size();
      ++frames;
    }
  }
  row.wall_s = watch.elapsedSeconds();
  row.cpu_s = threadCpuSeconds() - cpu0;
  row.sim_s = sim.time_s();
  row.rtf = row.sim_s / row.cpu_s;
  row.rtf_wall = row.sim_s / row.wall_s;
  row.mrays_per_s = sim.raysCast() / row.cpu_s / 1e6;
  row.pts_per_frame = frames ? static_cast<double>(points) / frames : 0.0;
  row.coverage = sim.coverage()->fraction();
  row.collided = sim.collided();
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const efs::CliArgs args(argc, argv, {"seconds", "worlds"}, {"small", "analytic-only"});
    const double seconds = args.number("seconds", 10.0);
    const bool small = args.flag("small");
    std::vector<Row> rows;

    {
      const AnalyticBoxWorld room = makeRoomWithPillar({20.0, 15.0, 4.0}, 4.0, 2.0, 1.0);
      rows.push_back(
          runOne("analytic box room 20x15x4", room, {-3, -2, 1.5}, 0.0, seconds, 0.0, 0.0, false));
      rows.push_back(
          runOne("analytic box room 20x15x4", room, {-3, -2, 1.5}, 0.0, seconds, 0.0, 0.0, true));
      const AnalyticBoxWorld hall = makePillarHall({48.0, 40.0, 4.0}, 8.0, 0.6);
      rows.push_back(runOne("analytic pillar hall 48x40x4", hall, {-20, -16, 1.5}, 0.0, seconds,
                            0.0, 0.0, false));
    }
#ifdef EFS_HAVE_WORLD_GENERATORS
    if (!args.flag("analytic-only")) {
      const WorldSize size = small ? WorldSize::kSmall : WorldSize::kPaper;
      std::vector<WorldKind> kinds;
      std::string list = args.str("worlds", "garage,subt_cave") + ",";
      for (std::size_t pos; (pos = list.find(',')) != std::string::npos; list.erase(0, pos + 1)) {
        if (pos > 0) kinds.push_back(parseWorldKind(list.substr(0, pos)));
      }
      for (WorldKind kind : kinds) {
        efs::Stopwatch w;
        const VoxelWorld world = generateWorld(kind, size, 1);
        const double build_s = w.elapsedSeconds();
        const StartPose& s = world.start_poses.at(0);
        rows.push_back(runOne(worldKindName(kind) + (small ? " (small)" : " (paper size)"), world,
                              s.position_m, s.yaw_rad, seconds, build_s,
                              world.memoryBytes() / 1048576.0, false));
      }
    }
#else
    std::printf("(world generators not available: voxel worlds skipped)\n");
#endif

    std::printf(
        "\nsim_bench: %.0f s simulated per world, Mid-360 200k pts/s (Avia 240k), "
        "500 Hz dynamics, 100 Hz stepping, one core\n\n",
        seconds);
    std::printf(
        "| world | build s | world MB | GT voxels | CPU s | RTF (CPU) | RTF (wall) | "
        "Mrays/s | pts/frame | coverage | collided |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const Row& r : rows) {
      std::printf("| %s | %.2f | %.1f | %zu | %.3f | %.1fx | %.1fx | %.2f | %.0f | %.3f | %s |\n",
                  r.world.c_str(), r.build_s, r.world_mb, r.gt_voxels, r.cpu_s, r.rtf, r.rtf_wall,
                  r.mrays_per_s, r.pts_per_frame, r.coverage, r.collided ? "yes" : "no");
    }
    std::printf(
        "\nRTF (CPU) = simulated time / this thread's CPU time (robust on a shared machine);"
        " RTF (wall) uses the wall clock.\nTarget: RTF >= 20x on the garage and the "
        "SubT-scale cave. Peak RSS %.0f MB.\n",
        efs::peakRssBytes() / 1048576.0);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sim_bench: %s\n", e.what());
    return 1;
  }
}
