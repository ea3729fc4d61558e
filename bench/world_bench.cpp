// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// world_bench: build time, memory and ray-casting throughput of every world at the paper's sizes
// (garage, simple cave, SubT-scale cave, indoor) and of the imported real ones (ed21, Pittsburgh
// mine). Rays follow a Mid-360-like field of view (360 deg azimuth, -7..52 deg elevation) at
// 40 m range from free, enclosed origins, on one core (CPU time).
// Prints a table; never asserts.
//
//   world_bench [--resolution 0.15] [--rays 2000000] [--worlds
//   garage,simple_cave,subt_cave,indoor,ed21,mine]
#include <cmath>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "efs_common/angles.h"
#include "efs_common/cli_args.h"
#include "efs_common/resource_usage.h"
#include "efs_common/testing/paths.h"
#include "marsim_worlds/seeded_random.h"
#include "marsim_worlds/world_generators.h"
#include "marsim_worlds/world_importers.h"
#include "marsim_worlds/world_sketch.h"

namespace {

using namespace efs::sim;

struct RayStats {
  double rays_per_s = 0.0;
  double hit_share = 0.0;
  double mean_range_m = 0.0;
  int origins = 0;
};

RayStats measureRays(const VoxelWorld& w, long total_rays) {
  SeededRandom rng(17);
  const Eigen::AlignedBox3d b = w.bounds();
  std::vector<Eigen::Vector3d> origins{w.start_poses.front().position_m};
  for (int tries = 0; origins.size() < 32 && tries < 2000000; ++tries) {
    const Eigen::Vector3d p(rng.uniform(b.min().x(), b.max().x()),
                            rng.uniform(b.min().y(), b.max().y()),
                            rng.uniform(b.min().z(), b.max().z()));
    if (w.collides(p, 0.5)) continue;
    bool enclosed = true;
    for (int k = 0; k < 8 && enclosed; ++k) {
      const double a = k * M_PI / 4.0;
      enclosed = std::isfinite(w.castRay(p, {std::cos(a), std::sin(a), 0.0}, 60.0));
    }
    if (enclosed) origins.push_back(p);
  }
  // One scan's worth of directions per origin, Mid-360-like.
  const int per_origin = 20000;
  std::vector<Eigen::Vector3f> dirs(per_origin);
  for (auto& d : dirs) {
    const double az = rng.uniform(-M_PI, M_PI);
    const double el = efs::deg2rad(rng.uniform(-7.0, 52.0));
    d = Eigen::Vector3f(static_cast<float>(std::cos(el) * std::cos(az)),
                        static_cast<float>(std::cos(el) * std::sin(az)),
                        static_cast<float>(std::sin(el)));
  }
  std::vector<float> ranges;
  long cast = 0, hits = 0;
  double sum_range = 0.0;
  // CPU time of this process, not wall time: the figure must not depend on what else the machine
  // is doing (CI runs benchmarks next to builds).
  const std::clock_t c0 = std::clock();
  for (size_t k = 0; cast < total_rays; ++k) {
    w.castRays(origins[k % origins.size()], dirs, 40.0, &ranges);
    cast += per_origin;
    for (float r : ranges) {
      if (std::isfinite(r)) {
        ++hits;
        sum_range += r;
      }
    }
  }
  RayStats s;
  s.rays_per_s = cast / (static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
  s.hit_share = static_cast<double>(hits) / cast;
  s.mean_range_m = hits ? sum_range / hits : 0.0;
  s.origins = static_cast<int>(origins.size());
  return s;
}

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const efs::CliArgs args(argc, argv, {"resolution", "rays", "worlds"});
    const double res = args.number("resolution", 0.15);
    const long rays = args.integer("rays", 2000000);
    const std::vector<std::string> worlds =
        split(args.str("worlds", "garage,simple_cave,subt_cave,indoor,ed21,mine"));
    std::printf("world_bench: resolution %.2f m, %ld rays per world at 40 m range, one core\n\n",
                res, rays);
    std::printf(
        "| world | size (m) | build (s) | world (MB) | peak RSS (MB) | masked bricks | full bricks "
        "| sketch (s) | rays/s (M) | hits | mean range (m) |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const std::string& name : worlds) {
      efs::resetPeakRss();
      efs::Stopwatch watch;
      VoxelWorld w = [&]() {
        ImportConfig ic;
        ic.resolution_m = res;
        if (name == "ed21")
          return importSdfWorld(efs::testing::sharedDataPath("ed21/ed21.world"), ic);
        if (name == "mine") {
          return importSdfWorld(
              efs::testing::sharedDataPath("pittsburgh_mine/pittsburgh_mine.world"), ic);
        }
        return generateWorld(parseWorldKind(name), WorldSize::kPaper, 1, res);
      }();
      const double build_s = watch.elapsedSeconds();
      watch.restart();
      const Sketch sk = drawSketch(w, SketchVariant::kPrecise, SketchConfig());
      const double sketch_s = watch.elapsedSeconds();
      const size_t peak = efs::peakRssBytes();
      const RayStats rs = measureRays(w, rays);
      const Eigen::Vector3d size = w.bounds().sizes();
      std::printf(
          "| %s | %.0f x %.0f x %.1f | %.2f | %.1f | %.0f | %zu | %zu | %.2f | %.2f | %.0f%% | "
          "%.1f |\n",
          name.c_str(), size.x(), size.y(), size.z(), build_s, w.memoryBytes() / 1e6, peak / 1e6,
          w.maskedBrickCount(), w.fullBrickCount(), sketch_s, rs.rays_per_s / 1e6,
          100.0 * rs.hit_share, rs.mean_range_m);
      std::fflush(stdout);
      (void)sk;
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "world_bench: " << e.what() << "\n";
    return 1;
  }
}
