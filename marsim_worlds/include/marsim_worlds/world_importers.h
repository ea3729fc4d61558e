// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Real worlds into VoxelWorld: Gazebo SDF worlds/models (box, cylinder and sphere primitives and
// meshes, each with its model/link/collision pose chain), meshes on their own (COLLADA, OBJ, STL,
// PLY via assimp) and PCD point clouds (own reader: ascii, binary, binary_compressed).
//
// Conventions:
//   - SDF poses are "x y z roll pitch yaw" (R = Rz(yaw) Ry(pitch) Rx(roll)), composed
//     model * link * collision. A world's <state> block holds the poses Gazebo applies when it
//     loads the world; they win over the models' own poses unless use_state_poses is false.
//     Collision geometry is used; a link without any falls back to its visuals.
//   - Surfaces are voxelised conservatively (every voxel a triangle or box touches), so the ray
//     caster cannot slip through a thin wall. Only the surface of a mesh is stored: rays and
//     flights start in free space and meet the surface first.
//   - The exploration box is the geometry's bounding box; floor and ceiling slabs (optional) sit
//     just below and above it. The start pose is the config's if given, else picked
//     deterministically: enclosed (horizontal rays hit walls all round), clear of obstacles by
//     start_clearance_m, with the most room, closest to the box centre.
//   - Every failure throws std::runtime_error (files) or efs::ConfigError (parameters) whose
//     message names the file and, where there is one, the line or key.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "efs_common/pcd_io.h"
#include "marsim_worlds/voxel_world.h"

namespace efs::sim {

struct ImportConfig {
  double resolution_m = 0.15;
  bool use_state_poses = true;
  bool add_floor = true;
  bool add_ceiling = true;
  double slab_thickness_m = 0.3;
  double margin_m = 1.0;  // free border around the geometry (x, y)
  double start_clearance_m = 0.8;
  double start_height_m = 1.2;  // above the floor, for the picked start
  bool has_start = false;       // use `start` instead of picking one
  StartPose start;
  int pcd_dilate_voxels = 1;  // closes gaps between the points of a cloud
  void validate() const;
};

struct Triangle {
  Eigen::Vector3d a, b, c;
};

/// Triangles of a mesh file (all meshes of the scene, node transforms applied), mapped by
/// T_world_mesh * diag(scale). Throws if the file cannot be read or has no triangles.
std::vector<Triangle> loadMeshTriangles(const std::string& path,
                                        const Eigen::Isometry3d& T_world_mesh,
                                        const Eigen::Vector3d& scale = Eigen::Vector3d::Ones());

using efs::loadPcdPoints;

/// Conservative triangle / axis-aligned box overlap (separating axis test, Akenine-Moeller 2001).
bool triangleOverlapsBox(const Eigen::Vector3d& box_centre, const Eigen::Vector3d& box_half,
                         const Triangle& tri);

VoxelWorld importSdfWorld(const std::string& sdf_path, const ImportConfig& config);
VoxelWorld importMeshWorld(const std::string& mesh_path, const Eigen::Isometry3d& T_world_mesh,
                           const ImportConfig& config);
VoxelWorld importPcdWorld(const std::string& pcd_path, const ImportConfig& config);

}  // namespace efs::sim
