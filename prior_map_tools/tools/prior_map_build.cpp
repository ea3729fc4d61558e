// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// prior_map_build: offline pre-processing of a sketch into a prior bundle (paper Sec. IV).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "efs_common/cli_args.h"
#include "efs_common/config_check.h"
#include "efs_common/resource_usage.h"
#include "prior_map_tools/prior_map_builder.h"
#include "prior_map_tools/prior_map_error.h"

namespace {

constexpr const char* kUsage =
    R"(usage: prior_map_build --sketch FILE --scale-guess M_PER_PX --mapping-range M --out FILE.prior [options]

Builds the prior bundle (traversable region, skeleton, guidepoints, PRM, distance matrix) of a
sketch: a drawing (PNG/JPG/PGM, grey, colour or alpha) or a map_server YAML occupancy grid.

  --sketch FILE          the sketch (map_server .yaml takes resolution and origin from the file)
  --scale-guess M        rough metres per pixel of a drawing (may be off by a factor of two)
  --mapping-range M      the robot's mapping range; guidepoints are spaced interval-factor x this
  --out FILE.prior       where to write the bundle
  --overlay FILE.png     where to write the picture for a person (default: OUT with .png)
  --summary FILE.json    also write the summary below as JSON
  --kind K               auto | drawing | grid                        (default auto)
  --robot-radius M       clearance from drawn walls                   (default 0.15)
  --max-outer-gap M      widest gap in the outer wall still sealed    (default 4.0)
  --min-region-area M2   smaller free components are dropped          (default 2.0)
  --min-enclosed-span F  an enclosed area spanning less than this      (default 0.5)
                         fraction of the strokes is a closet in an open outline
  --open-outline-gap M   an open outline's inside: what strokes so    (default 0)
                         near close, within their hull (0: all of it)
  --island-interiors X   drop | keep: the inside of a closed loop no  (default drop)
                         stroke joins to the outline (a pillar) is solid
  --spur-length M        skeleton spurs shorter than this are pruned  (default 2.0)
  --max-island M         islands (pillars) this small are filled for  (default 4.0)
                         the skeleton; 0 = off
  --interval-factor F    guidepoint spacing / mapping range           (default 3.0)
  --region-cover F       no place farther than F x the spacing from a (default 0.75)
                         guidepoint (open halls); 0 = skeleton only
  --prm-spacing M        mean PRM node spacing                        (default 1.5)
  --prm-k N              PRM neighbours per node                      (default 10)
  --seed N               PRM sampling seed                            (default 1)
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace efs::prior_map;
  try {
    const efs::CliArgs args(argc, argv,
                            {"sketch",
                             "scale-guess",
                             "mapping-range",
                             "out",
                             "overlay",
                             "summary",
                             "kind",
                             "robot-radius",
                             "max-outer-gap",
                             "min-region-area",
                             "min-enclosed-span",
                             "spur-length",
                             "max-island",
                             "region-cover",
                             "interval-factor",
                             "prm-spacing",
                             "prm-k",
                             "seed",
                             "island-interiors",
                             "open-outline-gap"},
                            {"help"});
    if (args.flag("help") || argc == 1) {
      std::cout << kUsage;
      return argc == 1 ? 2 : 0;
    }
    PriorMapConfig config;
    const std::string sketch_path = args.required("sketch");
    const std::string out_path = args.required("out");
    config.load.scale_guess_m_per_px = args.requiredNumber("scale-guess");
    config.guidepoints.mapping_range_m = args.requiredNumber("mapping-range");
    const std::string kind = args.str("kind", "auto");
    if (kind == "auto") {
      config.load.kind = SketchKind::kAuto;
    } else if (kind == "drawing") {
      config.load.kind = SketchKind::kLineDrawing;
    } else if (kind == "grid") {
      config.load.kind = SketchKind::kOccupancyGrid;
    } else {
      throw efs::CliError("option --kind must be auto, drawing or grid, got '" + kind + "'");
    }
    config.traversable.robot_radius_m =
        args.number("robot-radius", config.traversable.robot_radius_m);
    config.traversable.max_outer_gap_m =
        args.number("max-outer-gap", config.traversable.max_outer_gap_m);
    config.traversable.min_region_area_m2 =
        args.number("min-region-area", config.traversable.min_region_area_m2);
    config.traversable.min_enclosed_span_fraction =
        args.number("min-enclosed-span", config.traversable.min_enclosed_span_fraction);
    config.traversable.open_outline_gap_m =
        args.number("open-outline-gap", config.traversable.open_outline_gap_m);
    const std::string islands = args.str("island-interiors", "drop");
    if (islands != "drop" && islands != "keep")
      throw efs::CliError("option --island-interiors must be drop or keep, got '" + islands + "'");
    config.traversable.drop_island_interiors = islands == "drop";
    config.skeleton.spur_prune_length_m =
        args.number("spur-length", config.skeleton.spur_prune_length_m);
    config.skeleton.max_island_extent_m =
        args.number("max-island", config.skeleton.max_island_extent_m);
    config.guidepoints.interval_factor =
        args.number("interval-factor", config.guidepoints.interval_factor);
    config.guidepoints.region_cover_factor =
        args.number("region-cover", config.guidepoints.region_cover_factor);
    config.prm.node_spacing_m = args.number("prm-spacing", config.prm.node_spacing_m);
    config.prm.k_neighbours = static_cast<int>(args.integer("prm-k", config.prm.k_neighbours));
    config.prm.seed = static_cast<uint64_t>(args.integer("seed", 1));
    config.validate();

    const efs::Stopwatch watch;
    const LoadedSketch sketch = loadSketch(sketch_path, config.load);
    const PriorBundle bundle = buildPriorBundle(sketch, config);
    const double build_s = watch.elapsedSeconds();
    savePriorBundle(bundle, out_path);
    std::string overlay_path = args.str("overlay", "");
    if (overlay_path.empty()) {
      overlay_path = std::filesystem::path(out_path).replace_extension(".png").string();
    }
    if (!cv::imwrite(overlay_path, renderOverlay(bundle))) {
      throw PriorMapError(overlay_path + ": cannot write overlay image");
    }

    const PriorMapSummary s = summarize(bundle);
    std::printf("sketch              %s (%s, %d x %d px, %.4g m/px)\n", sketch_path.c_str(),
                toString(sketch.kind), sketch.frame.width_px, sketch.frame.height_px,
                sketch.frame.m_per_px);
    std::printf("region area         %.1f m^2 in %d component(s)\n", s.region_area_m2,
                s.components);
    std::printf("skeleton            %.1f m in %d branches\n", s.skeleton_length_m,
                s.skeleton_branches);
    std::printf("guidepoints         %d (interval %.1f m)\n", s.guidepoints,
                config.guidepoints.intervalM());
    std::printf("prm                 %d nodes, %d edges\n", s.prm_nodes, s.prm_edges);
    std::printf("unreachable pairs   %d\n", s.unreachable_pairs);
    std::printf("elapsed             %.3f s (peak memory %.1f MB)\n", build_s,
                efs::peakRssBytes() / 1e6);
    std::printf("wrote               %s, %s\n", out_path.c_str(), overlay_path.c_str());
    if (args.has("summary")) {
      const std::string json_path = args.required("summary");
      std::FILE* f = std::fopen(json_path.c_str(), "w");
      if (!f) throw PriorMapError(json_path + ": cannot write summary");
      std::fprintf(f,
                   "{\n  \"sketch\": \"%s\",\n  \"kind\": \"%s\",\n  \"width_px\": %d,\n"
                   "  \"height_px\": %d,\n  \"scale_guess_m_per_px\": %.6g,\n"
                   "  \"mapping_range_m\": %.6g,\n  \"region_area_m2\": %.3f,\n"
                   "  \"components\": %d,\n  \"skeleton_length_m\": %.3f,\n"
                   "  \"skeleton_branches\": %d,\n  \"guidepoints\": %d,\n"
                   "  \"guidepoint_interval_m\": %.3f,\n  \"prm_nodes\": %d,\n"
                   "  \"prm_edges\": %d,\n  \"unreachable_pairs\": %d,\n"
                   "  \"elapsed_s\": %.4f,\n  \"bundle\": \"%s\",\n  \"overlay\": \"%s\"\n}\n",
                   sketch_path.c_str(), toString(sketch.kind), sketch.frame.width_px,
                   sketch.frame.height_px, sketch.frame.m_per_px,
                   config.guidepoints.mapping_range_m, s.region_area_m2, s.components,
                   s.skeleton_length_m, s.skeleton_branches, s.guidepoints,
                   config.guidepoints.intervalM(), s.prm_nodes, s.prm_edges, s.unreachable_pairs,
                   build_s, out_path.c_str(), overlay_path.c_str());
      std::fclose(f);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "prior_map_build: error: %s\n", e.what());
    return 1;
  }
}
