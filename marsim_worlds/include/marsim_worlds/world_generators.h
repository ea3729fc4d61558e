// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Seeded, deterministic generators for the paper's four environment types (Section VII), at the
// paper's sizes and in a small (~40 m) size for tests. The same config and seed give the same
// world bit for bit on any platform (all randomness is SeededRandom / ValueNoise).
//
//   garage    192 x 150 x 4 m   high connectivity: parking modules, pillar grid, parked cars,
//                               cross aisles and partition walls with wide openings
//   simple    500 x 50 x 70 m   cave: one long rough tunnel with large height changes, few branches
//   subt     2024 x 330 x 41 m  cave: tunnel network with many branches and dead ends
//   indoor    150 x 110 x 4 m   irregular building: a corridor tree with rooms off it (doors),
//                               suites of rooms off rooms, low connectivity
//
// Caves are carved from solid rock as unions of capsules along a branching tunnel graph whose
// radius varies along the tunnels and whose walls are roughened by 3D value noise; buildings are
// carved from solid as rectangles from a floor plan (walls, floor and ceiling are what is left).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "marsim_worlds/voxel_world.h"

namespace efs::sim {

enum class WorldKind { kGarage, kSimpleCave, kSubtCave, kIndoor };
enum class WorldSize { kPaper, kSmall };

std::string worldKindName(WorldKind kind);  // "garage", "simple_cave", "subt_cave", "indoor"
/// Inverse of worldKindName; throws std::invalid_argument listing the valid names.
WorldKind parseWorldKind(const std::string& name);

struct CaveConfig {
  Eigen::Vector3d size_m{2024.0, 330.0, 41.0};
  double resolution_m = 0.15;
  uint64_t seed = 1;
  double tunnel_radius_m = 3.0;   // mean horizontal radius
  double radius_variation = 0.3;  // relative, node to node
  double vertical_squash = 1.25;  // > 1: tunnels lower than wide
  double wall_roughness_m = 0.5;  // amplitude of the wall noise
  double roughness_wavelength_m = 3.0;
  double segment_length_m = 8.0;
  double max_turn_rad = 0.45;        // heading change per segment
  double max_slope = 0.12;           // |dz/ds| along a tunnel
  double trunk_heading_pull = 0.15;  // 0..1: how strongly the trunk keeps running along +x
  double branch_probability = 0.2;   // per segment
  double min_branch_length_m = 20.0;
  double max_branch_length_m = 250.0;
  double total_length_m = 6000.0;  // tunnel length budget
  double start_clearance_m = 1.0;

  static CaveConfig subt(WorldSize size);
  static CaveConfig simple(WorldSize size);
  void validate() const;
};

struct GarageConfig {
  Eigen::Vector3d size_m{192.0, 150.0, 4.0};
  double resolution_m = 0.15;
  uint64_t seed = 1;
  double wall_thickness_m = 0.3;
  double bay_width_m = 2.5;  // along the aisle
  double bay_depth_m = 5.0;
  double aisle_width_m = 6.5;
  double pillar_size_m = 0.6;
  int bays_per_pillar = 3;
  double cross_aisle_spacing_m = 48.0;  // a bay-free crossing every so often
  double car_probability = 0.6;
  int service_cores = 2;  // stair/elevator blocks
  double start_clearance_m = 1.0;

  static GarageConfig preset(WorldSize size);
  void validate() const;
};

struct IndoorConfig {
  Eigen::Vector3d size_m{150.0, 110.0, 4.0};
  double resolution_m = 0.15;
  uint64_t seed = 1;
  double wall_thickness_m = 0.3;
  double corridor_width_m = 2.4;
  double min_corridor_segment_m = 8.0;
  double max_corridor_segment_m = 30.0;
  double corridor_branch_probability = 0.35;
  double corridor_length_m = 420.0;  // budget for the corridor tree
  double min_room_m = 4.0;
  double max_room_m = 13.0;
  int room_attempts = 1500;
  double suite_probability = 0.3;  // a room opens off another room rather than a corridor
  double door_width_m = 1.0;
  double door_height_m = 2.1;
  double start_clearance_m = 1.0;

  static IndoorConfig preset(WorldSize size);
  void validate() const;
};

VoxelWorld generateCave(const CaveConfig& config);
VoxelWorld generateGarage(const GarageConfig& config);
VoxelWorld generateIndoor(const IndoorConfig& config);

/// The preset of `kind` at `size`, with `seed` and `resolution_m` overriding the preset's.
VoxelWorld generateWorld(WorldKind kind, WorldSize size, uint64_t seed, double resolution_m = 0.15);

}  // namespace efs::sim
