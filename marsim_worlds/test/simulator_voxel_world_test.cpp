// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The simulator against the suite's real world representation (VoxelWorld) rather than an
// analytic scene: the WorldGeometry contract is all it relies on.
#include <gtest/gtest.h>

#include "marsim_worlds/simulator.h"
#include "marsim_worlds/voxel_world.h"

namespace efs::sim {
namespace {

// A solid block with a 10 x 8 x 3 m room and a 1 m pillar carved out / left in.
VoxelWorld carvedRoom() {
  const Eigen::AlignedBox3d extent(Eigen::Vector3d(-6, -5, -1), Eigen::Vector3d(6, 5, 4));
  VoxelWorld w(extent, 0.1, VoxelWorld::Fill::kSolid);
  w.fillBox(Eigen::AlignedBox3d(Eigen::Vector3d(-5, -4, 0), Eigen::Vector3d(5, 4, 3)), false);
  w.fillBox(Eigen::AlignedBox3d(Eigen::Vector3d(2, -0.5, 0), Eigen::Vector3d(3, 0.5, 3)), true);
  return w;
}

TEST(SimulatorOnVoxelWorld, ReturnsLieOnOccupiedVoxelsAndCoverageGrows) {
  const VoxelWorld world = carvedRoom();
  SimulatorConfig c;
  c.initial_position_m = Eigen::Vector3d(-2, 0, 1.5);
  c.lidar.range_noise_std_m = 0.0;
  Simulator sim(world, c);
  ObservableSurfaceConfig oc;
  oc.rays_per_point = 10000;
  sim.setCoverageGroundTruth(observableSurfaceKeys(
      world,
      freeSamplePoints(world,
                       Eigen::AlignedBox3d(Eigen::Vector3d(-5, -4, 0), Eigen::Vector3d(5, 4, 3)),
                       2.0, 0.4),
      oc));
  ASSERT_GT(sim.coverage()->totalVoxels(), 1000u);
  sim.advanceTo(1.0);
  ASSERT_FALSE(sim.collided());
  const Eigen::Vector3d o = sim.T_world_sensor().translation();
  const auto& pts = sim.latestScan().points_world;
  ASSERT_GT(pts.size(), 19000u);
  // Just behind each return is rock, just before it air (except rays grazing an edge, which
  // leave the voxel within the 1 cm probe).
  int bad = 0;
  for (const auto& p : pts) {
    const Eigen::Vector3d x = p.cast<double>(), d = (x - o).normalized();
    if (!world.occupiedAt(x + 0.01 * d) || world.occupiedAt(x - 0.01 * d)) ++bad;
  }
  EXPECT_LT(bad, static_cast<int>(pts.size() / 1000));
  const auto& log = sim.coverageLog();
  ASSERT_EQ(log.size(), 2u);
  EXPECT_GT(log[1].coverage_fraction, 0.4);
  EXPECT_LT(log[1].coverage_fraction, 1.0);  // the pillar hides the wall behind it
}

TEST(SimulatorOnVoxelWorld, FlyingIntoRockIsACollision) {
  const VoxelWorld world = carvedRoom();
  SimulatorConfig c;
  c.initial_position_m = Eigen::Vector3d(0, 0, 1.5);
  c.lidar_enabled = false;
  Simulator sim(world, c);
  SO3Command cmd;
  const Eigen::Vector3d f = c.quadrotor.mass_kg * Eigen::Vector3d(4.0, 0, c.quadrotor.gravity_m_s2);
  cmd.force_world_N = f;
  cmd.q_world_body_des =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), f.normalized());
  ASSERT_TRUE(sim.setCommand(cmd).accepted);
  sim.advanceTo(3.0);
  ASSERT_TRUE(sim.collided());
  // The pillar face is at x = 2.
  EXPECT_LT(sim.groundTruth().p_world_m.x(), 2.0 - c.vehicle_radius_m + 1e-9);
  EXPECT_GT(sim.groundTruth().p_world_m.x(), 1.5);
  EXPECT_FALSE(world.collides(sim.groundTruth().p_world_m, c.vehicle_radius_m));
}

}  // namespace
}  // namespace efs::sim
