// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Which world to load, as the tools, the simulator node and the benchmarks name it: a generated
// kind (at small or paper size, with a seed) or an imported file (Gazebo SDF of boxes or of a
// mesh model, a mesh, a PCD cloud).
#pragma once

#include <cstdint>
#include <set>
#include <string>

#include "efs_common/cli_args.h"

#include "marsim_worlds/voxel_world.h"

namespace efs::sim {

struct WorldSource {
  std::string kind = "simple_cave";  ///< garage | simple_cave | subt_cave | indoor
  std::string size = "small";        ///< small | paper
  uint64_t seed = 1;
  double resolution_m = 0.15;
  std::string sdf_path;   ///< if set, import this Gazebo world instead of generating
  std::string mesh_path;  ///< if set, import this mesh (COLLADA, OBJ, STL, PLY)
  std::string pcd_path;   ///< if set, import this point cloud

  /// Throws efs::ConfigError naming the key (unknown kind or size, several files, bad resolution).
  void validate() const;
  /// "garage (small, seed 3)" or the file name.
  std::string describe() const;
};

/// Generates or imports the world; throws with the file and problem on failure.
VoxelWorld loadWorld(const WorldSource& source);

/// The command-line options every tool uses to name a world: --world KIND, --size, --seed,
/// --resolution, --sdf, --mesh, --pcd (add them to the tool's CliArgs valued options).
const std::set<std::string>& worldSourceOptions();
/// A WorldSource from those options (`default_kind` when --world is absent); validated, so a bad
/// value throws efs::ConfigError naming the option's parameter.
WorldSource worldSourceFromArgs(const CliArgs& args,
                                const std::string& default_kind = "simple_cave");

}  // namespace efs::sim
