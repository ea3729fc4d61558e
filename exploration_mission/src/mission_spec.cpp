// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/mission_spec.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "efs_common/config_check.h"
#include "marsim_worlds/world_sketch.h"
#include "prior_guided_planner/baseline_mode.h"

namespace efs::mission {

bool MissionSpec::usesPrior() const {
  const planner::BaselineMode mode = planner::parseBaselineMode(method, "method");
  return mode == planner::BaselineMode::kProposed || mode == planner::BaselineMode::kGreedyPrior;
}

std::string MissionSpec::label() const {
  if (!usesPrior()) return method;
  const std::string sketch =
      sketch_path.empty() ? sketch_variant : std::filesystem::path(sketch_path).stem().string();
  return method + " (" + sketch + ")";
}

const std::set<std::string>& missionSpecOptions() {
  static const std::set<std::string> options = [] {
    std::set<std::string> o = sim::worldSourceOptions();
    o.insert({"method", "variant", "sketch-seed", "sketch", "scale-guess", "mapping-range"});
    return o;
  }();
  return options;
}

MissionSpec missionSpecFromArgs(const CliArgs& args, const std::string& default_world) {
  MissionSpec spec;
  spec.world = sim::worldSourceFromArgs(args, default_world);
  spec.method = args.str("method", spec.method);
  planner::parseBaselineMode(spec.method, "--method");
  spec.sketch_variant = args.str("variant", spec.sketch_variant);
  sim::parseSketchVariant(spec.sketch_variant);
  spec.sketch_seed = static_cast<uint64_t>(args.integer("sketch-seed", 1));
  spec.sketch_path = args.str("sketch", "");
  if (args.has("scale-guess")) spec.scale_guess_m_per_px = args.requiredNumber("scale-guess");
  spec.mapping_range_m = args.number("mapping-range", spec.mapping_range_m);
  requireThat(spec.sketch_path.empty() || spec.scale_guess_m_per_px.has_value(), "--scale-guess",
              "a user's sketch (--sketch) needs the scale guess in metres per pixel");
  return spec;
}

std::optional<MissionPrior> makeMissionPrior(const MissionSpec& spec, const sim::VoxelWorld& world,
                                             const std::string& sketch_png_out) {
  requireInRange("mapping_range_m", spec.mapping_range_m, 0.5, 200.0);
  if (!spec.usesPrior()) return std::nullopt;
  prior_map::PriorMapConfig prior_config;
  prior_config.guidepoints.mapping_range_m = spec.mapping_range_m;
  if (!spec.sketch_path.empty()) {
    const cv::Mat image = cv::imread(spec.sketch_path, cv::IMREAD_GRAYSCALE);
    if (image.empty()) throw std::runtime_error("cannot read sketch '" + spec.sketch_path + "'");
    return prepareMissionPrior(image, *spec.scale_guess_m_per_px, prior_config, std::nullopt, 1.0,
                               spec.sketch_path);
  }
  sim::SketchConfig sketch_config;
  sketch_config.seed = spec.sketch_seed;
  const sim::Sketch sketch =
      sim::drawSketch(world, sim::parseSketchVariant(spec.sketch_variant), sketch_config);
  if (!sketch_png_out.empty()) sim::saveSketch(sketch, sketch_png_out);
  return prepareMissionPrior(sketch.image,
                             spec.scale_guess_m_per_px.value_or(sketch.metres_per_pixel),
                             prior_config, sketch.T_world_sketch, sketch.metres_per_pixel,
                             spec.sketch_variant + " sketch of " + spec.world.describe());
}

std::unique_ptr<ExplorationMission> makeMission(const MissionSpec& spec, MissionConfig config,
                                                const std::string& sketch_png_out) {
  config.session.world = spec.world;
  config.exploration.planner.mode = planner::parseBaselineMode(spec.method, "method");
  requireInRange("mapping_range_m", spec.mapping_range_m, 0.5, 200.0);
  config.validate();
  sim::VoxelWorld world = sim::loadWorld(spec.world);
  std::optional<MissionPrior> prior = makeMissionPrior(spec, world, sketch_png_out);
  return std::make_unique<ExplorationMission>(config, std::move(world), std::move(prior));
}

}  // namespace efs::mission
