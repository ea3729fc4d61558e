// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/odometry_model.h"

#include <gtest/gtest.h>

#include <cmath>

#include "efs_common/config_check.h"

namespace efs::sim {
namespace {

QuadrotorState someState() {
  QuadrotorState s;
  s.p_world_m = Eigen::Vector3d(3, -2, 1.5);
  s.v_world_m_s = Eigen::Vector3d(1, 0.5, 0);
  s.q_world_body = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  s.omega_body_rad_s = Eigen::Vector3d(0.1, 0, 0.3);
  return s;
}

TEST(OdometryModel, WithoutNoiseItIsTheTruth) {
  OdometryModel m(OdometryNoiseConfig(), 1);
  m.advanceDrift(10.0);
  const QuadrotorState s = someState();
  const Odometry o = m.measure(s, 2.5);
  EXPECT_EQ(o.stamp_s, 2.5);
  EXPECT_EQ(o.p_world_m, s.p_world_m);
  EXPECT_EQ(o.v_world_m_s, s.v_world_m_s);
  EXPECT_EQ(o.omega_body_rad_s, s.omega_body_rad_s);
  EXPECT_LT(o.q_world_body.angularDistance(s.q_world_body), 1e-12);
}

TEST(OdometryModel, WhiteNoiseHasTheConfiguredStatistics) {
  OdometryNoiseConfig c;
  c.position_noise_std_m = 0.05;
  c.velocity_noise_std_m_s = 0.1;
  c.orientation_noise_std_rad = 0.01;
  OdometryModel m(c, 42);
  const QuadrotorState s = someState();
  const int n = 20000;
  Eigen::Vector3d sum_p = Eigen::Vector3d::Zero(), sq_p = Eigen::Vector3d::Zero();
  Eigen::Vector3d sq_v = Eigen::Vector3d::Zero();
  double sq_ang = 0.0;
  for (int i = 0; i < n; ++i) {
    const Odometry o = m.measure(s, 0.0);
    const Eigen::Vector3d e = o.p_world_m - s.p_world_m;
    sum_p += e;
    sq_p += e.cwiseProduct(e);
    sq_v += (o.v_world_m_s - s.v_world_m_s).cwiseAbs2();
    const double a = o.q_world_body.angularDistance(s.q_world_body);
    sq_ang += a * a;
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(sum_p[k] / n, 0.0, 4 * 0.05 / std::sqrt(n));
    EXPECT_NEAR(std::sqrt(sq_p[k] / n), 0.05, 0.05 * 0.03);
    EXPECT_NEAR(std::sqrt(sq_v[k] / n), 0.1, 0.1 * 0.03);
  }
  // The angle of a 3D isotropic Gaussian rotation vector has E[a^2] = 3 sigma^2.
  EXPECT_NEAR(std::sqrt(sq_ang / n), std::sqrt(3.0) * 0.01, 0.01 * 0.06);
}

// A random walk of sigma per sqrt(s): after T seconds its spread over many runs is sigma sqrt(T);
// the registered frame and the odometry drift together.
TEST(OdometryModel, DriftIsARandomWalkOfTheEstimatedFrame) {
  OdometryNoiseConfig c;
  c.position_drift_std_m_per_sqrt_s = 0.02;
  c.yaw_drift_std_rad_per_sqrt_s = 0.001;
  const int runs = 400;
  const double T = 20.0, dt = 0.05;
  double sq_x = 0.0, sq_yaw = 0.0;
  for (int r = 0; r < runs; ++r) {
    OdometryModel m(c, 1000 + r);
    for (int i = 0; i < static_cast<int>(T / dt); ++i) m.advanceDrift(dt);
    const Eigen::Isometry3d& T_est = m.T_est_world();
    sq_x += T_est.translation().x() * T_est.translation().x();
    const double yaw = std::atan2(T_est.rotation()(1, 0), T_est.rotation()(0, 0));
    sq_yaw += yaw * yaw;
    const QuadrotorState s = someState();
    const Odometry o = m.measure(s, T);
    ASSERT_LT((o.p_world_m - T_est * s.p_world_m).norm(), 1e-12);
  }
  EXPECT_NEAR(std::sqrt(sq_x / runs), 0.02 * std::sqrt(T), 0.02 * std::sqrt(T) * 0.12);
  EXPECT_NEAR(std::sqrt(sq_yaw / runs), 0.001 * std::sqrt(T), 0.001 * std::sqrt(T) * 0.12);
}

TEST(OdometryModel, SameSeedSameNoiseOtherSeedOtherNoise) {
  OdometryNoiseConfig c;
  c.position_noise_std_m = 0.1;
  OdometryModel a(c, 5), b(c, 5), d(c, 6);
  const QuadrotorState s = someState();
  const Odometry oa = a.measure(s, 0), ob = b.measure(s, 0), od = d.measure(s, 0);
  EXPECT_EQ(oa.p_world_m, ob.p_world_m);
  EXPECT_NE(oa.p_world_m, od.p_world_m);
}

TEST(OdometryModel, BadConfigNamesTheKey) {
  OdometryNoiseConfig c;
  c.yaw_drift_std_rad_per_sqrt_s = -0.1;
  try {
    OdometryModel m(c, 1);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("yaw_drift_std_rad_per_sqrt_s"), std::string::npos);
  }
}

}  // namespace
}  // namespace efs::sim
