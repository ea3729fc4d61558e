// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/quadrotor_dynamics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "efs_common/config_check.h"

namespace efs::sim {
namespace {

constexpr double kDt = 0.002;  // 500 Hz, the simulator's default physics rate

QuadrotorState hoverState(const QuadrotorConfig& c) {
  QuadrotorState s;
  s.p_world_m = Eigen::Vector3d(1, 2, 3);
  s.thrust_N = c.mass_kg * c.gravity_m_s2;
  return s;
}

void run(QuadrotorDynamics* q, double seconds) {
  const int n = static_cast<int>(std::lround(seconds / kDt));
  for (int i = 0; i < n; ++i) q->step(kDt);
}

double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

TEST(QuadrotorDynamics, HoverIsAnEquilibrium) {
  const QuadrotorConfig c;
  QuadrotorDynamics q(c, hoverState(c));
  run(&q, 5.0);
  EXPECT_LT((q.state().p_world_m - Eigen::Vector3d(1, 2, 3)).norm(), 1e-9);
  EXPECT_LT(q.state().v_world_m_s.norm(), 1e-9);
  EXPECT_LT(q.state().omega_body_rad_s.norm(), 1e-9);
  EXPECT_NEAR(q.state().q_world_body.norm(), 1.0, 1e-12);
}

// Vertical step of 1 m/s^2 through the rotor lag tau: a(t) = 1 - exp(-t / tau), so
// z(t) = t^2 / 2 - tau t + tau^2 (1 - exp(-t / tau)) (no drag).
TEST(QuadrotorDynamics, VerticalStepResponseFollowsTheRotorLag) {
  QuadrotorConfig c;
  c.linear_drag_N_s_per_m = 0.0;
  QuadrotorDynamics q(c, hoverState(c));
  SO3Command cmd = q.hoverCommand();
  cmd.force_world_N.z() = c.mass_kg * (c.gravity_m_s2 + 1.0);
  ASSERT_TRUE(q.setCommand(cmd).accepted);
  const double tau = c.rotor_time_constant_s;
  run(&q, tau);
  EXPECT_NEAR(q.state().thrust_N - c.mass_kg * c.gravity_m_s2, c.mass_kg * (1 - std::exp(-1.0)),
              1e-4);
  run(&q, 1.0 - tau);
  const double t = 1.0;
  const double z = 0.5 * t * t - tau * t + tau * tau * (1 - std::exp(-t / tau));
  EXPECT_NEAR(q.state().p_world_m.z() - 3.0, z, 1e-5);
  EXPECT_NEAR(q.state().v_world_m_s.z(), t - tau * (1 - std::exp(-t / tau)), 1e-5);
  EXPECT_LT(q.state().p_world_m.head<2>().norm() - Eigen::Vector2d(1, 2).norm(), 1e-9);
}

// Drag limits the speed: at a constant horizontal force F the terminal speed is F / drag.
TEST(QuadrotorDynamics, LinearDragGivesTheTerminalSpeed) {
  QuadrotorConfig c;
  c.linear_drag_N_s_per_m = 0.5;
  QuadrotorDynamics q(c, hoverState(c));
  // Tilt the thrust to produce 1 N forward while holding altitude.
  const Eigen::Vector3d f(1.0, 0.0, c.mass_kg * c.gravity_m_s2);
  SO3Command cmd = q.hoverCommand();
  cmd.force_world_N = f;
  cmd.q_world_body_des =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), f.normalized());
  ASSERT_TRUE(q.setCommand(cmd).accepted);
  run(&q, 15.0);
  EXPECT_NEAR(q.state().v_world_m_s.x(), 1.0 / 0.5, 0.01);
  EXPECT_NEAR(q.state().v_world_m_s.z(), 0.0, 0.01);
}

// A roll step of 0.3 rad settles within 0.3 s without excessive overshoot (kR, kOm as MARSIM's).
TEST(QuadrotorDynamics, AttitudeStepIsTrackedQuickly) {
  const QuadrotorConfig c;
  QuadrotorDynamics q(c, hoverState(c));
  SO3Command cmd = q.hoverCommand();
  const Eigen::Quaterniond q_des(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
  cmd.q_world_body_des = q_des;
  ASSERT_TRUE(q.setCommand(cmd).accepted);
  double max_roll = 0.0;
  for (int i = 0; i < 250; ++i) {  // 0.5 s
    q.step(kDt);
    const Eigen::Vector3d z = q.state().q_world_body * Eigen::Vector3d::UnitZ();
    max_roll = std::max(max_roll, std::atan2(-z.y(), z.z()));
    if (i == 150) {
      EXPECT_LT(angleBetween(q.state().q_world_body, q_des), 0.02);
    }
  }
  EXPECT_LT(angleBetween(q.state().q_world_body, q_des), 0.005);
  EXPECT_LT(max_roll, 0.3 * 1.25);
  EXPECT_GT(max_roll, 0.29);
}

// A 1 Hz roll oscillation of 0.2 rad, commanded with its rate as feedforward (as an SE(3)
// controller would), is tracked to within a few hundredths of a radian despite the rotor lag.
TEST(QuadrotorDynamics, SinusoidalAttitudeIsTrackedWithRateFeedforward) {
  const QuadrotorConfig c;
  QuadrotorDynamics q(c, hoverState(c));
  double max_err = 0.0;
  for (int i = 0; i < 1500; ++i) {  // 3 s
    const double t = i * kDt;
    const double w = 2 * M_PI * 1.0;
    SO3Command cmd = q.hoverCommand();
    cmd.q_world_body_des =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.2 * std::sin(w * t), Eigen::Vector3d::UnitX()));
    cmd.omega_body_des_rad_s = Eigen::Vector3d(0.2 * w * std::cos(w * t), 0, 0);
    ASSERT_TRUE(q.setCommand(cmd).accepted);
    q.step(kDt);
    if (t > 1.0) {
      const Eigen::Quaterniond q_ref(
          Eigen::AngleAxisd(0.2 * std::sin(w * (t + kDt)), Eigen::Vector3d::UnitX()));
      max_err = std::max(max_err, q.state().q_world_body.angularDistance(q_ref));
    }
  }
  EXPECT_LT(max_err, 0.03);
  EXPECT_GT(max_err, 1e-4);  // the lag is real: a perfect match would mean no dynamics
}

TEST(QuadrotorDynamics, AttitudeTargetHoversAtHoverThrustAndTracksYaw) {
  const QuadrotorConfig c;
  QuadrotorDynamics q(c, hoverState(c));
  AttitudeTargetCommand cmd;
  cmd.thrust_normalized = c.hover_thrust_normalized;
  cmd.q_world_body_des = Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitZ()));
  ASSERT_TRUE(q.setCommand(cmd).accepted);
  run(&q, 2.0);
  EXPECT_LT(angleBetween(q.state().q_world_body, cmd.q_world_body_des), 1e-3);
  EXPECT_LT(std::abs(q.state().p_world_m.z() - 3.0), 1e-6);  // yaw does not change thrust
  // Full thrust climbs at (thrust / hover - 1) g, limited by max_thrust_N.
  cmd.thrust_normalized = 1.0;
  ASSERT_TRUE(q.setCommand(cmd).accepted);
  run(&q, 0.5);
  double T;
  Eigen::Vector3d tau;
  q.controlOutput(&T, &tau);
  EXPECT_NEAR(T, std::min(c.max_thrust_N, c.mass_kg * c.gravity_m_s2 / c.hover_thrust_normalized),
              1e-9);
}

TEST(QuadrotorDynamics, BodyRateCommandIsTrackedAndSaturatedAtTheRateLimit) {
  const QuadrotorConfig c;
  QuadrotorDynamics q(c, hoverState(c));
  AttitudeTargetCommand cmd;
  cmd.type_mask = AttitudeTargetCommand::kIgnoreAttitude;
  cmd.body_rate_des_rad_s = Eigen::Vector3d(0, 0, 1.0);
  cmd.thrust_normalized = c.hover_thrust_normalized;
  ASSERT_TRUE(q.setCommand(cmd).accepted);
  run(&q, 1.0);
  EXPECT_NEAR(q.state().omega_body_rad_s.z(), 1.0, 0.01);
  cmd.body_rate_des_rad_s = Eigen::Vector3d(0, 0, 100.0);
  ASSERT_TRUE(q.setCommand(cmd).accepted);
  run(&q, 2.0);
  EXPECT_LE(q.state().omega_body_rad_s.cwiseAbs().maxCoeff(), c.max_body_rate_rad_s + 1e-12);
  EXPECT_NEAR(q.state().omega_body_rad_s.z(), c.max_body_rate_rad_s, 1e-9);
}

TEST(QuadrotorDynamics, NonFiniteCommandsAreRejectedAndTheLastValidOneHolds) {
  const QuadrotorConfig c;
  QuadrotorDynamics q(c, hoverState(c));
  SO3Command bad = q.hoverCommand();
  bad.force_world_N.x() = NAN;
  CommandStatus s = q.setCommand(bad);
  EXPECT_FALSE(s.accepted);
  EXPECT_NE(s.reason.find("force"), std::string::npos);
  bad = q.hoverCommand();
  bad.q_world_body_des.coeffs().setZero();
  EXPECT_FALSE(q.setCommand(bad).accepted);
  bad = q.hoverCommand();
  bad.kOm_Nm_s_per_rad.z() = INFINITY;
  EXPECT_FALSE(q.setCommand(bad).accepted);
  AttitudeTargetCommand at;
  at.thrust_normalized = NAN;
  s = q.setCommand(at);
  EXPECT_FALSE(s.accepted);
  EXPECT_NE(s.reason.find("thrust"), std::string::npos);
  at.thrust_normalized = 0.5;
  at.body_rate_des_rad_s.x() = -INFINITY;
  EXPECT_FALSE(q.setCommand(at).accepted);
  run(&q, 2.0);
  EXPECT_LT((q.state().p_world_m - Eigen::Vector3d(1, 2, 3)).norm(), 1e-9);
}

TEST(QuadrotorDynamics, BadConfigNamesTheKey) {
  QuadrotorConfig c;
  c.max_thrust_N = 5.0;  // below the weight
  try {
    QuadrotorDynamics q(c);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("max_thrust_N"), std::string::npos);
  }
  c = QuadrotorConfig();
  c.inertia_diag_kg_m2.y() = 0.0;
  EXPECT_THROW(c.validate(), ConfigError);
  c = QuadrotorConfig();
  c.mass_kg = NAN;
  EXPECT_THROW(c.validate(), ConfigError);
}

}  // namespace
}  // namespace efs::sim
