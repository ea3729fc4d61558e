// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// What a mission is, in the words of its callers (demo, benchmark, bag recorder): a world, a
// method, and the sketch to use — drawn by the product from the world (a variant, with the true
// placement known for evaluation) or a user's drawing with a scale guess. makeMission() turns it
// into a ready-to-fly ExplorationMission, the same way for every caller.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "efs_common/cli_args.h"
#include "exploration_mission/exploration_mission.h"

namespace efs::mission {

struct MissionSpec {
  sim::WorldSource world;
  std::string method = "proposed";  ///< proposed | prior_free | greedy_prior | nearest_frontier
  std::string sketch_variant = "deformed";  ///< drawn from the world when sketch_path is empty
  uint64_t sketch_seed = 1;
  std::string sketch_path;  ///< a user's drawing (no ground truth)
  /// Metres per pixel the user believes; for drawn sketches, the drawing's stated scale if unset.
  std::optional<double> scale_guess_m_per_px;
  double mapping_range_m = 5.0;  ///< guidepoint spacing base (paper Sec. IV-B)
  /// A short name for tables: "proposed (deformed)", "prior_free", "proposed (sketch_ed21_2)".
  std::string label() const;
  bool usesPrior() const;
};

/// The command-line options of a MissionSpec (the world options, --method, --variant,
/// --sketch-seed, --sketch, --scale-guess, --mapping-range) and their parsing.
const std::set<std::string>& missionSpecOptions();
MissionSpec missionSpecFromArgs(const CliArgs& args,
                                const std::string& default_world = "simple_cave");

/// The sketch of `spec` pre-processed for `world` (none when the method flies without one): the
/// user's drawing, or the world's own drawing of the spec's variant (written to `sketch_png_out`
/// when not empty) with its ground truth. Throws with a message naming what was wrong.
std::optional<MissionPrior> makeMissionPrior(const MissionSpec& spec, const sim::VoxelWorld& world,
                                             const std::string& sketch_png_out = "");

/// Loads or generates the world, prepares the sketch (written to `sketch_png_out` when not
/// empty and drawn here), and builds the mission. Throws with a message naming what was wrong.
std::unique_ptr<ExplorationMission> makeMission(const MissionSpec& spec, MissionConfig config,
                                                const std::string& sketch_png_out = "");

}  // namespace efs::mission
