// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// prior_map_bench: time and peak memory of the offline pre-processing (paper Sec. IV) on the four
// real ed21 sketches and on a generated SubT-scale tunnel-network sketch (2000 m x 330 m at
// 0.5 m/px). Target (issue 2): the SubT-scale sketch in under 5 s and under 1 GB on one core.
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <vector>

#include "efs_common/resource_usage.h"
#include "efs_common/testing/paths.h"
#include "prior_map_tools/prior_map_builder.h"

namespace {

using namespace efs::prior_map;

// A line drawing of a tunnel network: a meandering trunk along the long axis with seeded side
// branches, some of which fork again and end blind, like the DARPA SubT cave.
cv::Mat1b drawTunnelNetwork(double width_m, double height_m, double m_per_px, uint64_t seed) {
  const int w = static_cast<int>(width_m / m_per_px), h = static_cast<int>(height_m / m_per_px);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  cv::Mat1b free = cv::Mat1b::zeros(h, w);
  auto tunnel = [&](cv::Point2d a, double heading, double length_m) {
    const double step = 5.0 / m_per_px;
    cv::Point2d p = a;
    for (double s = 0; s < length_m / m_per_px; s += step) {
      heading += (u(rng) - 0.5) * 0.5;
      const cv::Point2d q = p + step * cv::Point2d(std::cos(heading), std::sin(heading));
      if (q.x < 10 || q.y < 10 || q.x > w - 10 || q.y > h - 10) break;
      const int thick = static_cast<int>((5.0 + 6.0 * u(rng)) / m_per_px);
      cv::line(free, p, q, cv::Scalar(255), thick);
      p = q;
    }
    return p;
  };
  cv::Point2d p(20, h / 2.0);
  const double trunk_step = 100.0;
  for (double x = 0; x < width_m - trunk_step; x += trunk_step) {
    const cv::Point2d next(std::min(w - 20.0, p.x + trunk_step / m_per_px),
                           h * (0.3 + 0.4 * u(rng)));
    cv::line(free, p, next, cv::Scalar(255), static_cast<int>(8.0 / m_per_px));
    // Two or three branches per 100 m of trunk, north or south, some forking.
    const int branches = 2 + static_cast<int>(u(rng) * 2);
    for (int b = 0; b < branches; ++b) {
      const cv::Point2d start = p + (next - p) * u(rng);
      const double heading = (u(rng) < 0.5 ? -1 : 1) * (M_PI / 2 + (u(rng) - 0.5));
      const cv::Point2d end = tunnel(start, heading, 40.0 + 100.0 * u(rng));
      if (u(rng) < 0.4) tunnel(end, heading + (u(rng) - 0.5) * 2.0, 30.0 + 60.0 * u(rng));
    }
    p = next;
  }
  cv::Mat1b grown, drawing(h, w, uint8_t(255));
  cv::dilate(free, grown, cv::getStructuringElement(cv::MORPH_RECT, {3, 3}));
  drawing.setTo(0, grown & ~free);
  return drawing;
}

struct Row {
  std::string name;
  std::string size;
  double seconds;
  double peak_mb;
  PriorMapSummary summary;
};

Row measure(const std::string& name, const LoadedSketch& sketch, const PriorMapConfig& config) {
  efs::resetPeakRss();
  const size_t before = efs::currentRssBytes();
  const efs::Stopwatch watch;
  const PriorBundle b = buildPriorBundle(sketch, config);
  const double s = watch.elapsedSeconds();
  const double peak = (efs::peakRssBytes() - std::min(before, efs::peakRssBytes())) / 1e6;
  char size[64];
  std::snprintf(size, sizeof(size), "%dx%d px", sketch.frame.width_px, sketch.frame.height_px);
  return {name, size, s, peak, summarize(b)};
}

}  // namespace

int main() {
  std::vector<Row> rows;
  for (const char* name :
       {"sketch_ed21.png", "sketch_ed21_1.png", "sketch_ed21_2.png", "sketch_ed21_3.png"}) {
    PriorMapConfig config;
    config.load.scale_guess_m_per_px = 0.12;
    config.guidepoints.mapping_range_m = 5.0;
    try {
      const LoadedSketch s =
          loadSketch(efs::testing::sharedDataPath(std::string("ed21/") + name), config.load);
      rows.push_back(measure(std::string("ed21 ") + name, s, config));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "skipping %s: %s\n", name, e.what());
    }
  }
  {
    PriorMapConfig config;
    config.load.scale_guess_m_per_px = 0.5;
    config.guidepoints.mapping_range_m = 10.0;
    config.prm.node_spacing_m = 3.0;
    const cv::Mat1b drawing = drawTunnelNetwork(2000.0, 330.0, 0.5, 7);
    const LoadedSketch s = sketchFromImage(drawing, config.load, "subt_scale_generated");
    rows.push_back(measure("SubT-scale 2000x330 m", s, config));
  }

  std::printf(
      "\nprior_map_bench: offline pre-processing, one core (target SubT-scale: < 5 s, < 1 GB)\n\n");
  std::printf(
      "| sketch | size | time [s] | peak mem [MB] | area [m^2] | comps | skeleton [m] | "
      "guidepoints | PRM nodes | PRM edges |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    std::printf("| %s | %s | %.3f | %.0f | %.0f | %d | %.0f | %d | %d | %d |\n", r.name.c_str(),
                r.size.c_str(), r.seconds, r.peak_mb, r.summary.region_area_m2,
                r.summary.components, r.summary.skeleton_length_m, r.summary.guidepoints,
                r.summary.prm_nodes, r.summary.prm_edges);
  }
  return 0;
}
