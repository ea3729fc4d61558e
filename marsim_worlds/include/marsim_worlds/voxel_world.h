// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The simulator's world: a sparse two-level voxel grid that holds the paper's largest world
// (SubT-scale cave, 2024 x 330 x 41 m) at 0.1-0.2 m in well under 2 GB.
//
// Level 1 is a dense grid of 8^3-voxel bricks, one int32 per brick: either an index into a pool
// of 512-bit occupancy masks, or one of two sentinels that store nothing: kEmptyBrick (all free)
// and kFullBrick (all occupied). Generated caves and buildings start solid and are carved, so
// rock far from any passage costs 4 bytes per brick and the interior of solid stays solid (a
// sphere inside rock collides, a ray starting in rock returns 0). Only bricks cut by a surface
// carry a mask. Level 2 is the mask itself.
//
// Rays are cast with a two-level Amanatides-Woo DDA: whole empty bricks are crossed in one step,
// a full brick is a hit at its entry, and only masked bricks are walked voxel by voxel. Surfaces
// imported from meshes are voxelised conservatively (every voxel a triangle touches), so the DDA,
// which visits every voxel a ray passes through, cannot slip through a one-voxel-thin shell.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "marsim_worlds/world_geometry.h"

namespace efs::sim {

/// Where a flight may start: position and heading in the world frame.
struct StartPose {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
};

/// What a person drawing the world's sketch would look at: walls between these heights.
struct SketchBand {
  double z_min_m = 1.0;
  double z_max_m = 1.8;
};

class VoxelWorld final : public WorldGeometry {
 public:
  static constexpr int kBrickShift = 3;
  static constexpr int kBrickEdge = 1 << kBrickShift;  // voxels per brick edge
  static constexpr int kBrickMask = kBrickEdge - 1;
  /// Brick-slot sentinels (slot >= 0 indexes the mask pool).
  static constexpr int32_t kEmptyBrick = -1;
  static constexpr int32_t kFullBrick = -2;
  /// Bricks beyond this count would make the level-1 grid alone larger than 4 GB.
  static constexpr int64_t kMaxBricks = int64_t{1} << 30;

  enum class Fill { kFree, kSolid };

  /// One brick's occupancy: bit (x + 8 y) of rows[z], x/y/z the voxel's offset in the brick.
  struct BrickMask {
    std::array<uint64_t, kBrickEdge> rows{};
  };

  /// A grid covering `extent_m` (rounded up to whole bricks) at `resolution_m`, all free or all
  /// solid. The exploration box defaults to `extent_m`. Throws efs::ConfigError naming
  /// 'resolution_m' or 'extent_m' for absurd values (including grids too large to allocate).
  VoxelWorld(const Eigen::AlignedBox3d& extent_m, double resolution_m, Fill initial = Fill::kFree);

  // --- WorldGeometry ---------------------------------------------------------------------------
  void castRays(const Eigen::Vector3d& origin_m, const std::vector<Eigen::Vector3f>& dirs_unit,
                double max_range_m, std::vector<float>* ranges_m) const override;
  bool collides(const Eigen::Vector3d& p_m, double radius_m) const override;
  /// The exploration bounding box.
  Eigen::AlignedBox3d bounds() const override { return exploration_box_m_; }

  /// One ray; kNoHit if nothing occupied lies within `max_range_m`. Outside the grid is free.
  float castRay(const Eigen::Vector3d& origin_m, const Eigen::Vector3d& dir_unit,
                double max_range_m) const;

  // --- voxel access --------------------------------------------------------------------------
  double resolution() const { return resolution_m_; }
  const Eigen::Vector3d& origin() const { return origin_m_; }  // min corner of voxel (0,0,0)
  const Eigen::Vector3i& dimsVoxels() const { return dims_vox_; }
  const Eigen::Vector3i& dimsBricks() const { return dims_bricks_; }
  /// Extent of the voxel grid (>= the extent given to the constructor).
  Eigen::AlignedBox3d gridBox() const;

  bool inGrid(const Eigen::Vector3i& v) const {
    return (v.array() >= 0).all() && (v.array() < dims_vox_.array()).all();
  }
  Eigen::Vector3i voxelOf(const Eigen::Vector3d& p_m) const;
  Eigen::Vector3d voxelCenter(const Eigen::Vector3i& v) const {
    return origin_m_ + (v.cast<double>().array() + 0.5).matrix() * resolution_m_;
  }
  /// Occupancy of a voxel; outside the grid is free.
  bool occupied(const Eigen::Vector3i& v) const;
  bool occupiedAt(const Eigen::Vector3d& p_m) const { return occupied(voxelOf(p_m)); }
  /// Slot of a brick (kEmptyBrick, kFullBrick or a pool index); the brick must be in the grid.
  int32_t brickSlot(const Eigen::Vector3i& b) const { return bricks_[brickLinear(b)]; }

  // --- editing (generators, importers) --------------------------------------------------------
  void setVoxel(const Eigen::Vector3i& v, bool occupied);
  /// Sets every voxel whose cell overlaps `box_m` (clipped to the grid); whole bricks become
  /// sentinels without touching the pool.
  void fillBox(const Eigen::AlignedBox3d& box_m, bool occupied);
  /// Sets voxels in `box_m` whose centre satisfies `signed_distance(centre) < 0` to `occupied`.
  /// `signed_distance` must be `lipschitz`-Lipschitz (|f(a)-f(b)| <= L |a-b|) so that whole bricks
  /// can be classified from their centre: that is what makes carving kilometres of tunnel cheap.
  template <class SignedDistance>
  void paint(const Eigen::AlignedBox3d& box_m, bool occupied, double lipschitz,
             const SignedDistance& signed_distance);
  /// Merges bricks that became uniform into sentinels and recycles their masks.
  void compact();

  // --- metadata ------------------------------------------------------------------------------
  std::string name;
  std::vector<StartPose> start_poses;
  SketchBand sketch_band;
  void setExplorationBox(const Eigen::AlignedBox3d& box_m) { exploration_box_m_ = box_m; }

  /// Throws std::invalid_argument naming the pose if any start pose lies outside the exploration
  /// box or within `clearance_m` of an obstacle; also if there is none.
  void validateStartPoses(double clearance_m) const;
  /// Distance (to `max_m`, at voxel precision) from `p_m` to the nearest occupied voxel.
  double clearance(const Eigen::Vector3d& p_m, double max_m) const;

  /// Top-down map of the grid (dimsVoxels().x() * dimsVoxels().y(), x fastest): 1 where the
  /// column holds a free voxel with its centre in [z_min_m, z_max_m], else 0. Brick-wise, so the
  /// SubT-scale world takes well under a second.
  std::vector<uint8_t> freeColumns(double z_min_m, double z_max_m) const;

  // --- statistics ----------------------------------------------------------------------------
  std::size_t memoryBytes() const;
  std::size_t maskedBrickCount() const { return pool_.size() - free_slots_.size(); }
  std::size_t fullBrickCount() const;
  /// Number of occupied voxels (full bricks count 512 each).
  std::size_t occupiedVoxelCount() const;
  /// Hash of the grid geometry and occupancy (not of the pool layout): equal worlds, equal hash.
  uint64_t fingerprint() const;

 private:
  static Eigen::Vector3i brickOf(const Eigen::Vector3i& v) {
    return {v.x() >> kBrickShift, v.y() >> kBrickShift, v.z() >> kBrickShift};
  }
  int64_t brickLinear(const Eigen::Vector3i& b) const {
    return b.x() + static_cast<int64_t>(dims_bricks_.x()) *
                       (b.y() + static_cast<int64_t>(dims_bricks_.y()) * b.z());
  }
  int32_t allocateMask(bool all_occupied);
  void releaseMask(int32_t slot);
  /// Makes brick `b` hold a mask (converting a sentinel) and returns the slot.
  int32_t materialise(int64_t brick_linear);
  void setBrickUniform(int64_t brick_linear, bool occupied);

  double resolution_m_ = 0.1;
  double inv_resolution_ = 10.0;
  Eigen::Vector3d origin_m_ = Eigen::Vector3d::Zero();
  Eigen::Vector3i dims_vox_ = Eigen::Vector3i::Zero();
  Eigen::Vector3i dims_bricks_ = Eigen::Vector3i::Zero();
  Eigen::AlignedBox3d exploration_box_m_;
  std::vector<int32_t> bricks_;
  std::vector<BrickMask> pool_;
  std::vector<int32_t> free_slots_;
};

/// `extent_m` with its bottom lowered so that height `z_boundary_m` falls on a brick boundary of a
/// grid at `resolution_m`. Used for ceilings: most LiDAR rays go up, and a ceiling that fills
/// whole bricks is hit at the brick level without walking voxels (about twice the rays/s indoors).
Eigen::AlignedBox3d alignBrickBoundary(const Eigen::AlignedBox3d& extent_m, double z_boundary_m,
                                       double resolution_m);

// ------------------------------------------------------------------------------------------------

template <class SignedDistance>
void VoxelWorld::paint(const Eigen::AlignedBox3d& box_m, bool occ, double lipschitz,
                       const SignedDistance& signed_distance) {
  const Eigen::AlignedBox3d clipped = box_m.intersection(gridBox());
  if (clipped.isEmpty()) return;
  const Eigen::Vector3i v_lo = voxelOf(clipped.min()).cwiseMax(0);
  const Eigen::Vector3i v_hi = voxelOf(clipped.max()).cwiseMin(dims_vox_ - Eigen::Vector3i::Ones());
  const Eigen::Vector3i b_lo = v_lo.array() / kBrickEdge;
  const Eigen::Vector3i b_hi = v_hi.array() / kBrickEdge;
  // Centre-to-corner distance of a brick's voxel centres, scaled by the Lipschitz bound.
  const double brick_reach = lipschitz * std::sqrt(3.0) * 0.5 * (kBrickEdge - 1) * resolution_m_;
  for (int bz = b_lo.z(); bz <= b_hi.z(); ++bz) {
    for (int by = b_lo.y(); by <= b_hi.y(); ++by) {
      for (int bx = b_lo.x(); bx <= b_hi.x(); ++bx) {
        const Eigen::Vector3i b(bx, by, bz);
        const int64_t lin = brickLinear(b);
        const int32_t slot = bricks_[lin];
        if ((slot == kFullBrick && occ) || (slot == kEmptyBrick && !occ)) continue;
        const Eigen::Vector3i v0 = b * kBrickEdge;
        const Eigen::Vector3i lo = v0.cwiseMax(v_lo);
        const Eigen::Vector3i hi = (v0.array() + kBrickMask).matrix().cwiseMin(v_hi);
        const bool whole_brick = lo == v0 && hi == (v0.array() + kBrickMask).matrix();
        const Eigen::Vector3d centre =
            origin_m_ + (v0.cast<double>().array() + 0.5 * kBrickEdge).matrix() * resolution_m_;
        const double d = signed_distance(centre);
        if (d > brick_reach) continue;  // no voxel centre of this brick is inside
        if (whole_brick && d < -brick_reach) {
          setBrickUniform(lin, occ);
          continue;
        }
        for (int z = lo.z(); z <= hi.z(); ++z) {
          for (int y = lo.y(); y <= hi.y(); ++y) {
            for (int x = lo.x(); x <= hi.x(); ++x) {
              const Eigen::Vector3i v(x, y, z);
              if (signed_distance(voxelCenter(v)) < 0.0) setVoxel(v, occ);
            }
          }
        }
      }
    }
  }
}

}  // namespace efs::sim
