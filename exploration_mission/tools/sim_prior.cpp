// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// sim_prior: draws a simulated world's sketch of one variant, as a person would, and pre-processes
// it into the prior bundle the flight stack loads (the same code as explore_mission). Prints the
// bundle's path and nothing else on stdout, so that sim_explore.launch can run it at launch time
// (<param command="...">) before any node starts. An existing bundle made from the same arguments
// is reused (its .args file beside it records them).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "efs_common/cli_args.h"
#include "exploration_mission/mission_spec.h"
#include "prior_map_tools/prior_bundle.h"

namespace {

constexpr const char* kUsage =
    R"(usage: sim_prior [world options] --variant V [--sketch-seed N] [--scale-guess M] --out FILE

Draws the world's sketch (precise | partial | deformed | scaled), writes FILE (the prior bundle),
FILE.png (the drawing), FILE.args and FILE.truth.yaml (the true placement of the bundle's sketch
frame in the world, for evaluation only: nothing in the flight stack reads it), and prints FILE. World options as explore_mission:
--world KIND --size SIZE --seed N --resolution M, or --sdf/--mesh/--pcd FILE.
--scale-guess M: the metres per pixel the user believes (default: the drawing's stated scale).
Exit status: 0 success, 2 bad input.
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace efs;
  try {
    std::set<std::string> options = mission::missionSpecOptions();
    options.insert("out");
    const CliArgs args(argc, argv, options, {"help"});
    if (args.flag("help")) {
      std::cout << kUsage;
      return 0;
    }
    const std::string out = args.required("out");
    mission::MissionSpec spec = mission::missionSpecFromArgs(args);
    spec.method = "proposed";
    if (!spec.sketch_path.empty()) {
      throw std::invalid_argument("--sketch: a user's drawing is pre-processed by prior_map_build");
    }
    std::ostringstream key;
    for (int i = 1; i < argc; ++i) key << argv[i] << '\n';
    const std::string args_file = out + ".args";
    {
      std::ifstream in(args_file);
      std::stringstream previous;
      previous << in.rdbuf();
      if (in && previous.str() == key.str() && std::filesystem::exists(out)) {
        std::cout << out;  // no newline: roslaunch stores the output verbatim
        return 0;
      }
    }
    const std::filesystem::path parent = std::filesystem::path(out).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    const sim::VoxelWorld world = sim::loadWorld(spec.world);
    const auto prior = mission::makeMissionPrior(spec, world, out + ".png");
    prior_map::savePriorBundle(prior->bundle, out);
    if (prior->T_world_sketch_truth)
      mission::saveTruth(*prior->T_world_sketch_truth, out + ".truth.yaml");
    std::ofstream(args_file) << key.str();
    std::cerr << "sim_prior: " << prior->description << " -> " << out << " ("
              << prior->bundle.guidepoints.size() << " guidepoints)\n";
    std::cout << out;  // no newline: roslaunch stores the output verbatim
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "sim_prior: " << e.what() << "\n";
    return 2;
  }
}
