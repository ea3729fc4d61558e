// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/simulator.h"
#include "efs_common/testing/config_error.h"

#include <gtest/gtest.h>

#include <cmath>

#include "efs_common/config_check.h"
#include "marsim_worlds/analytic_worlds.h"

namespace efs::sim {
namespace {

SimulatorConfig baseConfig(const Eigen::Vector3d& start) {
  SimulatorConfig c;
  c.initial_position_m = start;
  return c;
}

/// An SO3 command asking for world acceleration `a` (plus gravity) at yaw 0.
SO3Command accelCommand(const SimulatorConfig& c, const Eigen::Vector3d& a) {
  SO3Command cmd;
  const Eigen::Vector3d f =
      c.quadrotor.mass_kg * (a + Eigen::Vector3d(0, 0, c.quadrotor.gravity_m_s2));
  cmd.force_world_N = f;
  cmd.q_world_body_des =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), f.normalized());
  return cmd;
}

TEST(Simulator, TimeAdvancesInWholePhysicsStepsAndFramesComeAt10Hz) {
  const AnalyticBoxWorld room = makeBoxRoom({10.0, 8.0, 3.0});
  Simulator sim(room, baseConfig({0, 0, 1.5}));
  EXPECT_EQ(sim.latestScan().seq, 0u);
  EXPECT_EQ(sim.odometrySeq(), 1u);
  sim.advanceTo(0.0999);
  EXPECT_EQ(sim.physicsSteps(), 49u);
  EXPECT_EQ(sim.latestScan().seq, 0u);
  sim.step(0.0011);
  EXPECT_EQ(sim.physicsSteps(), 50u);
  EXPECT_DOUBLE_EQ(sim.time_s(), 0.1);
  ASSERT_EQ(sim.latestScan().seq, 1u);
  EXPECT_EQ(sim.raysCast(), 20000u);                        // 200k points/s
  EXPECT_EQ(sim.latestScan().points_world.size(), 20000u);  // closed room: all return
  EXPECT_DOUBLE_EQ(sim.latestScan().stamp_end_s, 0.1);
  EXPECT_EQ(sim.odometrySeq(), 11u);  // t = 0 plus 10 at 100 Hz
  sim.advanceTo(1.0);
  EXPECT_EQ(sim.latestScan().seq, 10u);
  EXPECT_EQ(sim.raysCast(), 200000u);
  EXPECT_DOUBLE_EQ(sim.latestOdometry().stamp_s, 1.0);
  // Hover: the vehicle stays put.
  EXPECT_LT((sim.groundTruth().p_world_m - Eigen::Vector3d(0, 0, 1.5)).norm(), 1e-9);
}

// Callers stepping by less than a physics step lose no time: requests accumulate.
TEST(Simulator, ShortStepsAccumulate) {
  const AnalyticBoxWorld room = makeBoxRoom({10.0, 8.0, 3.0});
  SimulatorConfig c = baseConfig({0, 0, 1.5});
  c.lidar_enabled = false;
  Simulator sim(room, c);
  for (int i = 0; i < 10; ++i) sim.step(0.0005);
  EXPECT_EQ(sim.physicsSteps(), 2u);  // 5 ms at 500 Hz
  sim.advanceTo(0.001);               // the past: nothing happens
  EXPECT_EQ(sim.physicsSteps(), 2u);
  sim.step(NAN);
  EXPECT_EQ(sim.physicsSteps(), 2u);
  EXPECT_EQ(sim.latestScan().seq, 0u);  // LiDAR disabled
}

// The Avia-like sensor looks forward only: in a closed room all its returns lie ahead.
TEST(Simulator, AviaScansLookForward) {
  const AnalyticBoxWorld room = makeBoxRoom({10.0, 8.0, 3.0});
  SimulatorConfig c = baseConfig({0, 0, 1.5});
  c.lidar.pattern = LivoxPatternConfig::avia();
  c.lidar.mount_pitch_rad = 0.0;
  Simulator sim(room, c);
  sim.advanceTo(0.1);
  ASSERT_EQ(sim.latestScan().seq, 1u);
  EXPECT_EQ(sim.latestScan().points_world.size(), 24000u);
  for (const auto& p : sim.latestScan().points_world) ASSERT_GT(p.x(), 0.0f);
}

TEST(Simulator, ScanPointsLieOnTheRoomWallsWhileFlying) {
  const AnalyticBoxWorld room = makeRoomWithPillar({12.0, 8.0, 3.0}, 3.0, 0.0, 0.8);
  SimulatorConfig c = baseConfig({-3, 0, 1.5});
  c.lidar.range_noise_std_m = 0.0;
  Simulator sim(room, c);
  ASSERT_TRUE(sim.setCommand(accelCommand(c, {1.0, 0.5, 0.0})).accepted);
  sim.advanceTo(1.5);
  ASSERT_FALSE(sim.collided());
  ASSERT_GT(sim.groundTruth().v_world_m_s.norm(), 1.0);
  const ScanFrame& f = sim.latestScan();
  ASSERT_EQ(f.seq, 15u);
  ASSERT_GT(f.points_world.size(), 19000u);
  for (const auto& p : f.points_world) {
    ASSERT_LT(room.distanceToSurface(p.cast<double>()), 1e-3);
  }
}

TEST(Simulator, CollisionIsReportedAndTheVehicleStopsBeforeTheWall) {
  const AnalyticBoxWorld room = makeBoxRoom({10.0, 10.0, 3.0});
  SimulatorConfig c = baseConfig({0, 0, 1.5});
  Simulator sim(room, c);
  ASSERT_TRUE(sim.setCommand(accelCommand(c, {3.0, 0.0, 0.0})).accepted);
  sim.advanceTo(5.0);
  ASSERT_TRUE(sim.collided());
  const CollisionReport& r = *sim.collision();
  EXPECT_GT(r.stamp_s, 1.0);
  EXPECT_LT(r.stamp_s, 2.5);
  const Eigen::Vector3d p = sim.groundTruth().p_world_m;
  EXPECT_EQ(p, r.position_m);
  EXPECT_LE(p.x(), 5.0 - c.vehicle_radius_m);
  EXPECT_GT(p.x(), 4.5);
  EXPECT_FALSE(room.collides(p, c.vehicle_radius_m));
  EXPECT_TRUE(room.collides(r.attempted_position_m, c.vehicle_radius_m));
  EXPECT_EQ(sim.groundTruth().v_world_m_s.norm(), 0.0);
  // It stays stopped, and time and the LiDAR go on.
  const double travelled = sim.travelledDistance_m();
  sim.advanceTo(6.0);
  EXPECT_EQ(sim.groundTruth().p_world_m, p);
  EXPECT_EQ(sim.travelledDistance_m(), travelled);
  EXPECT_EQ(sim.latestScan().seq, 60u);
}

// A wall thinner than one physics step's travel at full speed is still not passed through.
TEST(Simulator, FastVehicleDoesNotTunnelThroughAThinWall) {
  AnalyticBoxWorld room = makeBoxRoom({60.0, 10.0, 3.0});
  room.addSolidBox(
      Eigen::AlignedBox3d(Eigen::Vector3d(20.0, -5.0, 0.0), Eigen::Vector3d(20.005, 5.0, 3.0)));
  SimulatorConfig c = baseConfig({-25, 0, 1.5});
  c.quadrotor.linear_drag_N_s_per_m = 0.0;
  c.physics_rate_hz = 200.0;
  c.lidar_enabled = false;
  Simulator sim(room, c);
  ASSERT_TRUE(sim.setCommand(accelCommand(c, {20.0, 0.0, 0.0})).accepted);
  sim.advanceTo(10.0);
  ASSERT_TRUE(sim.collided());
  EXPECT_LT(sim.groundTruth().p_world_m.x(), 20.0 - c.vehicle_radius_m + 1e-9);
  EXPECT_GT(sim.groundTruth().p_world_m.x(), 19.0);
}

TEST(Simulator, NaNCommandIsRejectedAndTheVehicleHolds) {
  const AnalyticBoxWorld room = makeBoxRoom({10.0, 10.0, 3.0});
  SimulatorConfig c = baseConfig({1, 1, 1.5});
  Simulator sim(room, c);
  SO3Command bad = accelCommand(c, {1, 0, 0});
  bad.force_world_N.y() = std::numeric_limits<double>::quiet_NaN();
  const CommandStatus s = sim.setCommand(bad);
  EXPECT_FALSE(s.accepted);
  EXPECT_EQ(sim.rejectedCommands(), 1u);
  EXPECT_EQ(sim.lastRejection(), s.reason);
  AttitudeTargetCommand at;
  at.q_world_body_des.coeffs() << 0, 0, INFINITY, 1;
  EXPECT_FALSE(sim.setCommand(at).accepted);
  EXPECT_EQ(sim.rejectedCommands(), 2u);
  sim.advanceTo(3.0);
  EXPECT_FALSE(sim.collided());
  EXPECT_LT((sim.groundTruth().p_world_m - Eigen::Vector3d(1, 1, 1.5)).norm(), 1e-9);
  EXPECT_TRUE(sim.latestOdometry().p_world_m.allFinite());
}

TEST(Simulator, SameSeedSameRunOtherSeedOtherNoise) {
  const AnalyticBoxWorld room = makeRoomWithPillar({12.0, 8.0, 3.0}, 3.0, 0.0, 0.8);
  SimulatorConfig c = baseConfig({-3, 0, 1.5});
  c.odometry.position_noise_std_m = 0.05;
  c.odometry.position_drift_std_m_per_sqrt_s = 0.01;
  auto run = [&](uint64_t seed) {
    SimulatorConfig cs = c;
    cs.seed = seed;
    auto sim = std::make_unique<Simulator>(room, cs);
    sim->setCommand(accelCommand(cs, {0.5, 0.2, 0.1}));
    sim->advanceTo(0.5);
    return sim;
  };
  const auto a = run(3), b = run(3), d = run(4);
  ASSERT_EQ(a->latestScan().points_world.size(), b->latestScan().points_world.size());
  EXPECT_TRUE(std::equal(a->latestScan().points_world.begin(), a->latestScan().points_world.end(),
                         b->latestScan().points_world.begin()));
  EXPECT_EQ(a->latestOdometry().p_world_m, b->latestOdometry().p_world_m);
  EXPECT_EQ(a->groundTruth().p_world_m, b->groundTruth().p_world_m);
  EXPECT_NE(a->latestOdometry().p_world_m, d->latestOdometry().p_world_m);
  EXPECT_NE(a->latestScan().points_world[0], d->latestScan().points_world[0]);
  EXPECT_EQ(a->groundTruth().p_world_m, d->groundTruth().p_world_m);  // noise never feeds back
}

// With drift the registered scan is expressed in the drifting estimated frame, consistently with
// the odometry: mapped back through T_est_world it lies on the true walls again.
TEST(Simulator, DriftMovesScanAndOdometryTogether) {
  const AnalyticBoxWorld room = makeBoxRoom({12.0, 8.0, 3.0});
  SimulatorConfig c = baseConfig({0, 0, 1.5});
  c.lidar.range_noise_std_m = 0.0;
  c.odometry.position_drift_std_m_per_sqrt_s = 0.05;
  c.odometry.yaw_drift_std_rad_per_sqrt_s = 0.01;
  Simulator sim(room, c);
  sim.advanceTo(4.0);
  const Eigen::Isometry3d T = sim.T_est_world();
  EXPECT_GT(T.translation().norm(), 1e-3);
  EXPECT_LT((sim.latestOdometry().p_world_m - T * sim.groundTruth().p_world_m).norm(), 1e-9);
  // The last batch of the frame was registered with the final drift; earlier ones with slightly
  // older drift (a random walk of ~0.05 m/sqrt(s) over 0.1 s), so allow for that.
  int on_wall = 0;
  const auto& pts = sim.latestScan().points_world;
  for (const auto& p : pts) {
    if (room.distanceToSurface(T.inverse() * p.cast<double>()) < 0.05) ++on_wall;
  }
  EXPECT_GT(on_wall, static_cast<int>(0.99 * pts.size()));
}

// Full-sphere sensor in a small room: everything is visible from the start, so coverage reaches
// exactly 1; the log is monotone.
TEST(Simulator, CoverageIsMonotoneAndReachesOneInAFullyVisibleRoom) {
  const AnalyticBoxWorld room(
      Eigen::AlignedBox3d(Eigen::Vector3d(-1.95, -1.95, 0.15), Eigen::Vector3d(1.95, 1.95, 2.55)));
  SimulatorConfig c = baseConfig({0, 0, 1.35});
  c.lidar.pattern.elevation_min_rad = -M_PI / 2;
  c.lidar.pattern.elevation_max_rad = M_PI / 2;
  c.lidar.mount_pitch_rad = 0.0;
  c.lidar.t_body_sensor_m.setZero();
  c.coverage_log_period_s = 0.1;
  Simulator sim(room, c);
  ObservableSurfaceConfig oc;
  oc.rays_per_point = 100000;
  const VoxelKeySet gt = observableSurfaceKeys(room, {c.initial_position_m}, oc);
  sim.setCoverageGroundTruth(gt);
  ASSERT_NE(sim.coverage(), nullptr);
  EXPECT_EQ(sim.coverage()->fraction(), 0.0);
  sim.advanceTo(3.0);
  const auto& log = sim.coverageLog();
  ASSERT_EQ(log.size(), 31u);
  for (std::size_t i = 1; i < log.size(); ++i) {
    EXPECT_GE(log[i].coverage_fraction, log[i - 1].coverage_fraction);
    EXPECT_NEAR(log[i].stamp_s, 0.1 * i, 1e-9);
  }
  EXPECT_GT(log[1].coverage_fraction, 0.5);  // one frame sees most of it
  EXPECT_EQ(sim.coverage()->fraction(), 1.0);
  EXPECT_TRUE(sim.coverage()->finished());
}

// With the default pitched Mid-360 in a room with a pillar, flying across the room increases
// coverage monotonically and the travelled distance matches the ground truth path.
TEST(Simulator, CoverageAndDistanceLogWhileFlying) {
  const AnalyticBoxWorld room = makeRoomWithPillar({12.0, 8.0, 3.0}, 0.0, 0.0, 1.0);
  SimulatorConfig c = baseConfig({-4, -3, 1.5});
  Simulator sim(room, c);
  ObservableSurfaceConfig oc;
  oc.rays_per_point = 20000;
  sim.setCoverageGroundTruth(
      observableSurfaceKeys(room, freeSamplePoints(room, room.bounds(), 1.0, 0.5), oc));
  ASSERT_GT(sim.coverage()->totalVoxels(), 1000u);
  ASSERT_TRUE(sim.setCommand(accelCommand(c, {1.0, 0.5, 0.0})).accepted);
  sim.advanceTo(2.0);
  ASSERT_TRUE(sim.setCommand(accelCommand(c, {-1.0, -0.5, 0.0})).accepted);
  sim.advanceTo(4.0);
  ASSERT_FALSE(sim.collided());
  const auto& log = sim.coverageLog();
  ASSERT_EQ(log.size(), 5u);
  for (std::size_t i = 1; i < log.size(); ++i) {
    EXPECT_GE(log[i].coverage_fraction, log[i - 1].coverage_fraction);
    EXPECT_GE(log[i].travelled_distance_m, log[i - 1].travelled_distance_m);
  }
  EXPECT_GT(log.back().coverage_fraction, 0.3);
  EXPECT_LT(log.back().coverage_fraction, 1.0);
  // Accelerate 2 s, decelerate 2 s at |a| = 1.118 m/s^2: at most 4.47 m (drag and rotor lag take
  // a little), along a nearly straight line, so the path length is about the displacement.
  const double displacement = (sim.groundTruth().p_world_m - c.initial_position_m).norm();
  EXPECT_GT(displacement, 3.5);
  EXPECT_LT(sim.travelledDistance_m(), 4.47);
  EXPECT_GE(sim.travelledDistance_m(), displacement - 1e-9);
  EXPECT_LT(sim.travelledDistance_m(), displacement + 0.2);
}

TEST(Simulator, BadStartPosesAndConfigsNameTheKey) {
  const AnalyticBoxWorld room = makeRoomWithPillar({10.0, 10.0, 3.0}, 0.0, 0.0, 1.0);
  auto expectKey = [&](const SimulatorConfig& c, const std::string& key) {
    efs::testing::expectConfigErrorNaming([&] { Simulator sim(room, c); }, key);
  };
  expectKey(baseConfig({0, 0, 1.5}), "initial_position_m");   // inside the pillar
  expectKey(baseConfig({50, 0, 1.5}), "initial_position_m");  // outside the bounds
  expectKey(baseConfig({3, 3, 0.1}), "initial_position_m");   // touching the floor
  SimulatorConfig c = baseConfig({3, 3, 1.5});
  c.physics_rate_hz = 50.0;
  expectKey(c, "physics_rate_hz");
  c = baseConfig({3, 3, 1.5});
  c.lidar.frame_rate_hz = 0.0;
  expectKey(c, "frame_rate_hz");
  c = baseConfig({3, 3, 1.5});
  c.quadrotor.rotor_time_constant_s = 0.002;
  expectKey(c, "rotor_time_constant_s");
  c = baseConfig({3, 3, NAN});
  expectKey(c, "initial_position_m");
}

}  // namespace
}  // namespace efs::sim
