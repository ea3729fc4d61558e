// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/world_source.h"

#include "efs_common/config_check.h"
#include "marsim_worlds/world_generators.h"
#include "marsim_worlds/world_importers.h"

namespace efs::sim {

void WorldSource::validate() const {
  const int files = !sdf_path.empty() + !mesh_path.empty() + !pcd_path.empty();
  requireThat(files <= 1, "world_sdf", "give at most one of world_sdf, world_mesh, world_pcd");
  if (files == 0) {
    requireThat(
        kind == "garage" || kind == "simple_cave" || kind == "subt_cave" || kind == "indoor",
        "world_kind", "'" + kind + "' is not garage, simple_cave, subt_cave or indoor");
    requireThat(size == "small" || size == "paper", "world_size",
                "'" + size + "' is not small or paper");
  }
  requireInRange("world_resolution_m", resolution_m, 0.02, 2.0);
}

std::string WorldSource::describe() const {
  if (!sdf_path.empty()) return sdf_path;
  if (!mesh_path.empty()) return mesh_path;
  if (!pcd_path.empty()) return pcd_path;
  return kind + " (" + size + ", seed " + std::to_string(seed) + ")";
}

VoxelWorld loadWorld(const WorldSource& source) {
  source.validate();
  ImportConfig ic;
  ic.resolution_m = source.resolution_m;
  if (!source.sdf_path.empty()) return importSdfWorld(source.sdf_path, ic);
  if (!source.mesh_path.empty())
    return importMeshWorld(source.mesh_path, Eigen::Isometry3d::Identity(), ic);
  if (!source.pcd_path.empty()) return importPcdWorld(source.pcd_path, ic);
  return generateWorld(parseWorldKind(source.kind),
                       source.size == "small" ? WorldSize::kSmall : WorldSize::kPaper, source.seed,
                       source.resolution_m);
}

const std::set<std::string>& worldSourceOptions() {
  static const std::set<std::string> options{"world", "size", "seed", "resolution",
                                             "sdf",   "mesh", "pcd"};
  return options;
}

WorldSource worldSourceFromArgs(const CliArgs& args, const std::string& default_kind) {
  WorldSource source;
  source.kind = args.str("world", default_kind);
  source.size = args.str("size", source.size);
  const long seed = args.integer("seed", static_cast<long>(source.seed));
  requireInRange("seed", seed, 0L, 1L << 40);
  source.seed = static_cast<uint64_t>(seed);
  source.resolution_m = args.number("resolution", source.resolution_m);
  source.sdf_path = args.str("sdf", "");
  source.mesh_path = args.str("mesh", "");
  source.pcd_path = args.str("pcd", "");
  source.validate();
  return source;
}

}  // namespace efs::sim
