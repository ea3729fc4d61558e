// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "efs_common/config_check.h"
#include "se3_controller/se3_controller.h"

namespace efs::control {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

OdometryState hoverOdom(double t, const Eigen::Vector3d& p = Eigen::Vector3d(0, 0, 1)) {
  OdometryState o;
  o.stamp_s = t;
  o.p_world_m = p;
  return o;
}
FlatReference hoverRef(double t, const Eigen::Vector3d& p = Eigen::Vector3d(0, 0, 1)) {
  FlatReference r;
  r.stamp_s = t;
  r.p_world_m = p;
  return r;
}

/// Odometry loss handled without a reference to follow (the brake, hold and descent path).
Se3ControllerConfig brakeOnly() {
  Se3ControllerConfig c;
  c.feedforward_on_odometry_loss_s = 0.0;
  return c;
}

TEST(Se3Controller, HoverEquilibrium) {
  Se3Controller c;
  const auto out = c.update(hoverOdom(1.0), hoverRef(1.0), 1.0);
  const double mg = c.config().mass_kg * c.config().gravity_mps2;
  EXPECT_EQ(out.mode, ControlMode::kTracking);
  EXPECT_TRUE(out.reason.empty());
  EXPECT_LT((out.so3.force_world_N - Eigen::Vector3d(0, 0, mg)).norm(), 1e-12);
  EXPECT_LT(out.so3.orientation.angularDistance(Eigen::Quaterniond::Identity()), 1e-12);
  EXPECT_LT(out.so3.angular_velocity_body_radps.norm(), 1e-12);
  EXPECT_LT(out.attitude_error.norm(), 1e-12);
  EXPECT_NEAR(out.collective_thrust_N, mg, 1e-12);
  EXPECT_NEAR(out.attitude.thrust, c.config().hover_throttle_initial, 1e-12);
  EXPECT_EQ(out.so3.kR, c.config().kR);
  EXPECT_TRUE(out.so3.enable_motors);
}

TEST(Se3Controller, ErrorSigns) {
  Se3Controller c;
  const double mg = c.config().mass_kg * c.config().gravity_mps2;
  // Below the reference: more thrust.
  auto out = c.update(hoverOdom(0, {0, 0, 0.8}), hoverRef(0), 0);
  EXPECT_GT(out.so3.force_world_N.z(), mg);
  EXPECT_LT(out.position_error_m.z(), 0);
  // Displaced to +x: force and desired body z tilt toward -x (pitch negative about y).
  out = c.update(hoverOdom(0, {0.3, 0, 1}), hoverRef(0), 0);
  EXPECT_LT(out.so3.force_world_N.x(), 0);
  EXPECT_LT((out.so3.orientation * Eigen::Vector3d::UnitZ()).x(), 0);
  // Moving +y: braking force toward -y.
  OdometryState o = hoverOdom(0);
  o.v_world_mps = Eigen::Vector3d(0, 1, 0);
  out = c.update(o, hoverRef(0), 0);
  EXPECT_LT(out.so3.force_world_N.y(), 0);
  // Rolled about +x relative to a level desired attitude: attitude error along +x.
  o = hoverOdom(0);
  o.q_world_body = Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
  out = c.update(o, hoverRef(0), 0);
  EXPECT_GT(out.attitude_error.x(), 0.0);
  // Reference acceleration is fed forward.
  FlatReference r = hoverRef(0);
  r.a_world_mps2 = Eigen::Vector3d(2, 0, 0);
  out = c.update(hoverOdom(0), r, 0);
  EXPECT_NEAR(out.so3.force_world_N.x(), 2.0 * c.config().mass_kg, 1e-12);
  // Desired heading follows the reference yaw.
  r = hoverRef(0);
  r.yaw_rad = 1.0;
  out = c.update(hoverOdom(0), r, 0);
  const Eigen::Vector3d xb = out.so3.orientation * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(xb.y(), xb.x()), 1.0, 1e-12);
}

TEST(Se3Controller, TiltAndThrustAreBounded) {
  Se3ControllerConfig cfg;
  cfg.max_tilt_rad = 0.5;
  Se3Controller c(cfg);
  FlatReference r = hoverRef(0);
  r.a_world_mps2 = Eigen::Vector3d(30, 0, -20);
  const auto out = c.update(hoverOdom(0), r, 0);
  const Eigen::Vector3d z = out.so3.orientation * Eigen::Vector3d::UnitZ();
  EXPECT_LE(std::acos(z.z()), 0.5 + 1e-9);
  EXPECT_GE(out.so3.force_world_N.z(), cfg.min_thrust_accel_mps2 * cfg.mass_kg - 1e-12);
}

// Body rates from jerk must match the numerical derivative of the flat attitude.
TEST(Flatness, BodyRatesMatchNumericalDifferentiation) {
  auto a = [](double t) {
    return Eigen::Vector3d(3 * std::cos(1.3 * t), 2 * std::sin(0.9 * t), 1.5 * std::sin(2 * t));
  };
  auto j = [](double t) {
    return Eigen::Vector3d(-3.9 * std::sin(1.3 * t), 1.8 * std::cos(0.9 * t), 3 * std::cos(2 * t));
  };
  auto yaw = [](double t) { return 0.8 * std::sin(t) + 0.3 * t; };
  auto yawdot = [](double t) { return 0.8 * std::cos(t) + 0.3; };
  const double g = 9.81, h = 1e-6;
  for (double t = 0.0; t < 6.0; t += 0.37) {
    const FlatAttitude f = flatAttitude(a(t), j(t), yaw(t), yawdot(t), g);
    const Eigen::Matrix3d Rp =
        flatAttitude(a(t + h), j(t + h), yaw(t + h), yawdot(t + h), g).R_world_body;
    const Eigen::Matrix3d Rm =
        flatAttitude(a(t - h), j(t - h), yaw(t - h), yawdot(t - h), g).R_world_body;
    const Eigen::Matrix3d W = f.R_world_body.transpose() * (Rp - Rm) / (2 * h);
    const Eigen::Vector3d w_num(0.5 * (W(2, 1) - W(1, 2)), 0.5 * (W(0, 2) - W(2, 0)),
                                0.5 * (W(1, 0) - W(0, 1)));
    EXPECT_LT((w_num - f.omega_body_radps).norm(), 1e-6) << "t = " << t;
    // The body z axis is the thrust direction and the heading matches the yaw.
    const Eigen::Vector3d thrust = a(t) + Eigen::Vector3d(0, 0, g);
    EXPECT_LT((f.R_world_body.col(2) - thrust.normalized()).norm(), 1e-12);
    EXPECT_NEAR(f.thrust_accel_mps2, thrust.norm(), 1e-12);
    EXPECT_NEAR(f.R_world_body.col(1).dot(Eigen::Vector3d(std::cos(yaw(t)), std::sin(yaw(t)), 0)),
                0.0, 1e-12);
  }
}

TEST(Safety, StaleOdometryLevelsAndDescendsGently) {
  Se3Controller c(brakeOnly());
  const auto& cfg = c.config();
  OdometryState o = hoverOdom(0.0);
  o.q_world_body = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  c.update(o, hoverRef(0.0), 0.0);
  // 0.25 s later without new odometry (the same stale message keeps coming).
  auto out = c.update(o, hoverRef(0.25), 0.25);
  EXPECT_EQ(out.mode, ControlMode::kLevelDescend);
  EXPECT_NE(out.reason.find("odometry stale"), std::string::npos);
  const Eigen::Matrix3d Rd = out.so3.orientation.toRotationMatrix();
  EXPECT_LT((Rd.col(2) - Eigen::Vector3d::UnitZ()).norm(), 1e-12);  // level
  EXPECT_NEAR(std::atan2(Rd(1, 0), Rd(0, 0)), 0.7, 1e-9);           // keeps the last heading
  const double mg = cfg.mass_kg * cfg.gravity_mps2;
  // First the height is held (hover thrust) for descent_delay_s ...
  EXPECT_NEAR(out.so3.force_world_N.z(), mg, 1e-12);
  EXPECT_LT(out.so3.force_world_N.head<2>().norm(), 1e-12);
  // ... then the gentle descent starts ...
  const double t_descent = 0.25 + cfg.descent_delay_s + 0.1;
  out = c.update(o, hoverRef(t_descent), t_descent);
  EXPECT_NEAR(out.so3.force_world_N.z(), cfg.mass_kg * (cfg.gravity_mps2 - cfg.descent_accel_mps2),
              1e-12);
  EXPECT_LT(out.so3.force_world_N.head<2>().norm(), 1e-12);
  // ... and after the descent speed is reached the thrust returns to hover: constant slow descent.
  const double t_steady = t_descent + 5.0;
  out = c.update(o, hoverRef(t_steady), t_steady);
  EXPECT_NEAR(out.so3.force_world_N.z(), mg, 1e-12);
  // Fresh odometry brings tracking back.
  out = c.update(hoverOdom(t_steady), hoverRef(t_steady), t_steady);
  EXPECT_EQ(out.mode, ControlMode::kTracking);
}

TEST(Safety, StaleOdometryInMotionBrakesAgainstTheLastVelocityThenLevels) {
  Se3Controller c(brakeOnly());
  const auto& cfg = c.config();
  OdometryState o = hoverOdom(0.0);
  o.v_world_mps = Eigen::Vector3d(0.0, -3.0, 0.0);
  c.update(o, hoverRef(0.0), 0.0);
  auto out = c.update(o, hoverRef(0.25), 0.25);
  ASSERT_EQ(out.mode, ControlMode::kLevelDescend);
  const Eigen::Vector3d f = out.so3.force_world_N / cfg.mass_kg;
  EXPECT_NEAR(f.x(), 0.0, 1e-12);
  EXPECT_NEAR(f.y(), cfg.brake_accel_mps2, 1e-12);  // leaning against -y motion
  // |v| / a + the attitude lag after the onset (0.25 s) the brake ends and the attitude is level.
  const double brake_end_s = 0.25 + 3.0 / cfg.brake_accel_mps2 + cfg.brake_attitude_lag_s;
  out = c.update(o, hoverRef(brake_end_s - 0.01), brake_end_s - 0.01);
  EXPECT_GT(out.so3.force_world_N.y(), 0.0);
  out = c.update(o, hoverRef(brake_end_s + 0.01), brake_end_s + 0.01);
  EXPECT_LT(out.so3.force_world_N.head<2>().norm(), 1e-12);
}

TEST(Safety, StaleOdometryWithAFreshReferenceFollowsItOnDeadReckoningForABoundedTime) {
  Se3Controller c;
  const auto& cfg = c.config();
  OdometryState o = hoverOdom(0.0);
  c.update(o, hoverRef(0.0), 0.0);
  FlatReference r = hoverRef(0.3);
  r.p_world_m += Eigen::Vector3d(0.5, 0, 0);
  r.v_world_mps = Eigen::Vector3d(2.0, 0, 0);
  r.a_world_mps2 = Eigen::Vector3d(-1.0, 0.5, 0);
  auto out = c.update(o, r, 0.3);
  ASSERT_EQ(out.mode, ControlMode::kFeedForward);
  EXPECT_NE(out.reason.find("dead reckoning"), std::string::npos);
  // The dead-reckoned state (hovering at the last odometry) is fed back against the reference.
  const Eigen::Vector3d f = out.so3.force_world_N / cfg.mass_kg;
  EXPECT_GT(f.x(), r.a_world_mps2.x());  // pulled toward the reference 0.5 m ahead, 2 m/s
  EXPECT_EQ(out.mode, ControlMode::kFeedForward);
  // Past the feed-forward window the vehicle brakes and levels instead.
  const double late = cfg.odom_timeout_s + cfg.feedforward_on_odometry_loss_s + 0.1;
  r.stamp_s = late;
  out = c.update(o, r, late);
  EXPECT_EQ(out.mode, ControlMode::kLevelDescend);
  // A stale reference does not count either.
  Se3Controller c2;
  c2.update(o, hoverRef(0.0), 0.0);
  EXPECT_EQ(c2.update(o, hoverRef(0.0), 1.0).mode, ControlMode::kLevelDescend);
}

TEST(Safety, StaleCommandHoversAtTheLastPosition) {
  Se3Controller c;
  c.update(hoverOdom(0.0, {1, 2, 3}), hoverRef(0.0, {5, 5, 5}), 0.0);
  // The reference stops arriving while the robot is at (1.5, 2, 3).
  auto out = c.update(hoverOdom(1.0, {1.5, 2, 3}), hoverRef(0.0, {5, 5, 5}), 1.0);
  EXPECT_EQ(out.mode, ControlMode::kHoldPosition);
  EXPECT_NE(out.reason.find("reference stale"), std::string::npos);
  EXPECT_LT(out.position_error_m.norm(), 1e-12);  // holds where it was, not the old target
  // Drifting away from the latched point pulls back toward it.
  out = c.update(hoverOdom(1.1, {1.7, 2, 3}), hoverRef(0.0, {5, 5, 5}), 1.1);
  EXPECT_NEAR(out.position_error_m.x(), 0.2, 1e-12);
  EXPECT_LT(out.so3.force_world_N.x(), 0.0);
  EXPECT_LT(out.so3.angular_velocity_body_radps.norm(), 1e-12);
  // A fresh reference resumes tracking.
  out = c.update(hoverOdom(1.2, {1.7, 2, 3}), hoverRef(1.2, {5, 5, 5}), 1.2);
  EXPECT_EQ(out.mode, ControlMode::kTracking);
}

TEST(Safety, NoReferenceYetHoldsWhereTheVehicleIsEvenJustAfterTheClockStarts) {
  // A simulated clock starts at 0: a default reference (origin, stamp 0) would look fresh here.
  Se3Controller c;
  const double mg = c.config().mass_kg * c.config().gravity_mps2;
  auto out = c.update(hoverOdom(0.1, {5, 9, 10}), std::nullopt, 0.1);
  EXPECT_EQ(out.mode, ControlMode::kHoldPosition);
  EXPECT_NE(out.reason.find("no reference yet"), std::string::npos) << out.reason;
  EXPECT_LT(out.position_error_m.norm(), 1e-12);
  EXPECT_NEAR(out.so3.force_world_N.z(), mg, 1e-9);
  EXPECT_LT(out.so3.force_world_N.head<2>().norm(), 1e-12);
  // The first reference ends the hold.
  out = c.update(hoverOdom(0.2, {5, 9, 10}), hoverRef(0.2, {5, 9, 10}), 0.2);
  EXPECT_EQ(out.mode, ControlMode::kTracking);
}

TEST(Safety, NaNReferenceIsRejectedAndHovers) {
  Se3Controller c;
  FlatReference r = hoverRef(0.0, {3, 0, 1});
  r.a_world_mps2.x() = kNaN;
  const auto out = c.update(hoverOdom(0.0, {0, 0, 1}), r, 0.0);
  EXPECT_EQ(out.mode, ControlMode::kHoldPosition);
  EXPECT_NE(out.reason.find("reference rejected"), std::string::npos);
  EXPECT_TRUE(out.so3.force_world_N.allFinite());
  EXPECT_LT(out.position_error_m.norm(), 1e-12);
  FlatReference ry = hoverRef(0.0);
  ry.yaw_rad = kNaN;
  EXPECT_EQ(c.update(hoverOdom(0.0), ry, 0.0).mode, ControlMode::kHoldPosition);
}

TEST(Safety, NaNOdometryIsRejectedThenStalenessApplies) {
  Se3Controller c(brakeOnly());
  // Nothing valid yet: motors stay off.
  OdometryState bad = hoverOdom(0.0);
  bad.v_world_mps.y() = kNaN;
  auto out = c.update(bad, hoverRef(0.0), 0.0);
  EXPECT_EQ(out.mode, ControlMode::kNoOdometry);
  EXPECT_FALSE(out.so3.enable_motors);
  EXPECT_EQ(out.attitude.thrust, 0.0);
  // One valid message, then NaNs: the last valid state keeps the vehicle hovering.
  c.update(hoverOdom(1.0), hoverRef(1.0), 1.0);
  bad.stamp_s = 1.05;
  out = c.update(bad, hoverRef(1.05), 1.05);
  EXPECT_TRUE(out.odometry_rejected);
  EXPECT_NE(out.reason.find("odometry rejected"), std::string::npos);
  EXPECT_EQ(out.mode, ControlMode::kTracking);
  EXPECT_TRUE(out.so3.force_world_N.allFinite());
  // Still NaN 0.3 s after the last valid message: level and descend.
  out = c.update(bad, hoverRef(1.3), 1.3);
  EXPECT_EQ(out.mode, ControlMode::kLevelDescend);
  OdometryState badq = hoverOdom(1.3);
  badq.q_world_body.coeffs().setZero();
  EXPECT_TRUE(c.update(badq, hoverRef(1.3), 1.3).odometry_rejected);
  EXPECT_THROW(c.update(hoverOdom(0), hoverRef(0), kNaN), std::invalid_argument);
}

TEST(HoverThrottle, EstimateConvergesToTheVehiclesTrueValue) {
  Se3Controller c;
  // A vehicle whose true hover throttle is 0.35: commanded u gives a_z = (u / 0.35 - 1) g.
  const double truth = 0.35, g = c.config().gravity_mps2;
  double vz = 0, z = 1, t = 0;
  for (int k = 0; k < 1000; ++k) {  // 10 s at 100 Hz
    OdometryState o = hoverOdom(t, {0, 0, z});
    o.v_world_mps.z() = vz;
    const auto out = c.update(o, hoverRef(t), t);
    const double az = (out.attitude.thrust / truth - 1.0) * g;
    vz += az * 0.01;
    z += vz * 0.01;
    t += 0.01;
    // The next odometry message carries the acceleration produced by this command.
    OdometryState meas = hoverOdom(t, {0, 0, z});
    meas.v_world_mps.z() = vz;
    meas.has_acceleration = true;
    meas.a_world_mps2.z() = az;
    c.update(meas, hoverRef(t), t);
  }
  EXPECT_NEAR(c.hoverThrottle(), truth, 0.01);
}

TEST(Config, ValidateNamesTheKey) {
  Se3ControllerConfig cfg;
  cfg.odom_timeout_s = -1;
  try {
    cfg.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("se3.odom_timeout_s"), std::string::npos);
  }
  cfg = Se3ControllerConfig();
  cfg.hover_throttle_initial = 0.95;
  EXPECT_THROW(cfg.validate(), ConfigError);
  cfg = Se3ControllerConfig();
  cfg.kp_position.x() = kNaN;
  EXPECT_THROW(Se3Controller{cfg}, ConfigError);
}

}  // namespace
}  // namespace efs::control
