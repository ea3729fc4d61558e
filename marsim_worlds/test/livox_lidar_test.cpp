// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/livox_lidar.h"

#include <gtest/gtest.h>

#include <cmath>

#include "efs_common/config_check.h"
#include "marsim_worlds/analytic_worlds.h"

namespace efs::sim {
namespace {

// In a closed room every ray of the Mid-360 hits a wall; with noise every return lies within a
// few sigma of one (the noise is along the ray, so its distance to the plane is at most |n|).
TEST(LivoxLidar, EveryReturnInABoxRoomLiesOnAWallWithinTheNoise) {
  const AnalyticBoxWorld room = makeRoomWithPillar({12.0, 8.0, 3.0}, 2.0, 1.0, 0.8);
  LivoxLidarConfig cfg;
  cfg.range_noise_std_m = 0.02;
  LivoxLidar lidar(cfg, 7);
  LidarReturns out;
  const Eigen::Vector3d p(-1.0, -0.5, 1.2);
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()));
  const std::size_t cast = lidar.cast(room, 0, 20000, p, q, &out);
  EXPECT_EQ(cast, 20000u);
  EXPECT_EQ(out.points_world.size(), 20000u);  // closed room: no ray escapes
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < out.points_world.size(); ++i) {
    EXPECT_LT(room.distanceToSurface(out.surface_world[i].cast<double>()), 1e-4);
    const double d = room.distanceToSurface(out.points_world[i].cast<double>());
    EXPECT_LT(d, 5.0 * cfg.range_noise_std_m);
    const double dr = (out.points_world[i] - out.surface_world[i]).dot(out.dirs_world[i]);
    sum_sq += dr * dr;
  }
  const double sigma = std::sqrt(sum_sq / out.points_world.size());
  EXPECT_NEAR(sigma, cfg.range_noise_std_m, 0.05 * cfg.range_noise_std_m);
}

// The sensor's elevation band, pitched 15 deg forward-down, sees the floor ahead but not
// straight down: no return lies below the sensor at an angle steeper than 7 + 15 deg ahead.
TEST(LivoxLidar, MountPitchTiltsTheFieldOfViewForwardDown) {
  const AnalyticBoxWorld room = makeBoxRoom({40.0, 40.0, 10.0});
  LivoxLidarConfig cfg;
  cfg.range_noise_std_m = 0.0;
  cfg.t_body_sensor_m.setZero();
  LivoxLidar lidar(cfg, 1);
  LidarReturns out;
  const Eigen::Vector3d p(0, 0, 5.0);
  lidar.cast(room, 0, 200000, p, Eigen::Quaterniond::Identity(), &out);
  double min_el_fwd = 1e9, min_el_back = 1e9;
  for (const auto& x : out.points_world) {
    const Eigen::Vector3d v = x.cast<double>() - p;
    const double el = std::atan2(v.z(), std::hypot(v.x(), v.y()));
    if (std::abs(v.y()) < 0.05 * std::abs(v.x())) {
      (v.x() > 0 ? min_el_fwd : min_el_back) = std::min(v.x() > 0 ? min_el_fwd : min_el_back, el);
    }
  }
  EXPECT_NEAR(min_el_fwd * 180 / M_PI, -22.0, 1.0);
  EXPECT_NEAR(min_el_back * 180 / M_PI, 8.0, 1.0);
}

TEST(LivoxLidar, RangeLimitsDropReturns) {
  const AnalyticBoxWorld room = makeBoxRoom({100.0, 100.0, 100.0});
  LivoxLidarConfig cfg;
  cfg.max_range_m = 10.0;
  LivoxLidar lidar(cfg, 1);
  LidarReturns out;
  EXPECT_EQ(lidar.cast(room, 0, 5000, {0, 0, 50}, Eigen::Quaterniond::Identity(), &out), 5000u);
  EXPECT_TRUE(out.points_world.empty());
}

TEST(LivoxLidar, BadConfigNamesTheKey) {
  LivoxLidarConfig cfg;
  cfg.min_range_m = 50.0;
  try {
    cfg.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("min_range_m"), std::string::npos);
  }
  cfg = LivoxLidarConfig();
  cfg.range_noise_std_m = -1.0;
  EXPECT_THROW(cfg.validate(), ConfigError);
  cfg = LivoxLidarConfig();
  cfg.mount_pitch_rad = INFINITY;
  EXPECT_THROW(LivoxLidar(cfg, 1), ConfigError);
}

}  // namespace
}  // namespace efs::sim
