// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Closed-loop checks against a small rigid-body quadrotor written here for the test only (the
// suite's simulator lives in marsim_worlds). The inner loop mimics the so3 simulator's use of
// SO3Command: thrust = force . R e3, moment = -kR e_R - kOm e_Omega + Omega x J Omega.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "se3_controller/reference_shapes.h"
#include "se3_controller/se3_controller.h"

namespace efs::control {
namespace {

struct RigidBody {
  double mass_kg = 0.98, g = 9.81;
  Eigen::Matrix3d J = Eigen::Vector3d(2.64e-3, 2.64e-3, 4.96e-3).asDiagonal();
  Eigen::Vector3d p = Eigen::Vector3d(0, 0, 1), v = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d w = Eigen::Vector3d::Zero();

  static Eigen::Vector3d vee(const Eigen::Matrix3d& m) { return {m(2, 1), m(0, 2), m(1, 0)}; }
  static Eigen::Matrix3d expSO3(const Eigen::Vector3d& phi) {
    const double a = phi.norm();
    if (a < 1e-12) return Eigen::Matrix3d::Identity();
    return Eigen::AngleAxisd(a, phi / a).toRotationMatrix();
  }
  // Integrates dt under a held SO3 command (semi-implicit Euler, sub-stepped).
  void step(const So3CommandOut& c, double dt) {
    const Eigen::Matrix3d Rd = c.orientation.toRotationMatrix();
    const double f = std::max(0.0, c.force_world_N.dot(R.col(2)));
    const Eigen::Vector3d eR = 0.5 * vee(Rd.transpose() * R - R.transpose() * Rd);
    const Eigen::Vector3d eW = w - R.transpose() * Rd * c.angular_velocity_body_radps;
    const Eigen::Vector3d M = -c.kR.cwiseProduct(eR) - c.kOm.cwiseProduct(eW) + w.cross(J * w);
    const Eigen::Vector3d wdot = J.inverse() * (M - w.cross(J * w));
    const Eigen::Vector3d acc = f / mass_kg * R.col(2) - Eigen::Vector3d(0, 0, g);
    v += acc * dt;
    p += v * dt;
    w += wdot * dt;
    R = R * expSO3(w * dt);
  }
  OdometryState odom(double t) const {
    OdometryState o;
    o.stamp_s = t;
    o.p_world_m = p;
    o.v_world_mps = v;
    o.q_world_body = Eigen::Quaterniond(R);
    o.omega_body_radps = w;
    return o;
  }
};

/// Odometry loss handled without a reference to follow (the brake, hold and descent path).
Se3ControllerConfig brakeOnly() {
  Se3ControllerConfig c;
  c.feedforward_on_odometry_loss_s = 0.0;
  return c;
}

// Runs controller at 100 Hz and the body at 2 kHz; returns the RMS position error after `settle`.
template <typename RefFn, typename Hook>
double fly(Se3Controller& ctrl, RigidBody& body, RefFn ref_at, double duration, double settle,
           Hook hook, double* max_err = nullptr) {
  const double dt_ctrl = 0.01;
  const int sub = 20;
  double sum = 0;
  int n = 0;
  if (max_err) *max_err = 0;
  for (double t = 0; t < duration; t += dt_ctrl) {
    hook(t, body);
    const FlatReference r = ref_at(t);
    const ControlOutput out = ctrl.update(body.odom(t), r, t);
    for (int k = 0; k < sub; ++k) body.step(out.so3, dt_ctrl / sub);
    if (t >= settle) {
      const double e = (body.p - ref_at(t + dt_ctrl).p_world_m).norm();
      sum += e * e;
      ++n;
      if (max_err) *max_err = std::max(*max_err, e);
    }
  }
  return std::sqrt(sum / std::max(1, n));
}

TEST(ClosedLoop, HoverHoldsWithinFiveCentimetres) {
  Se3Controller ctrl;
  RigidBody body;
  body.p = Eigen::Vector3d(0.02, -0.02, 1.02);  // start slightly off
  const Eigen::Vector3d target(0, 0, 1);
  double max_err = 0;
  auto ref = [&](double t) {
    FlatReference r;
    r.stamp_s = t;
    r.p_world_m = target;
    r.yaw_rad = 0.5;
    return r;
  };
  fly(
      ctrl, body, ref, 6.0, 0.0, [](double, RigidBody&) {}, &max_err);
  EXPECT_LT(max_err, 0.05);
  EXPECT_LT((body.p - target).norm(), 0.005);
  const Eigen::Vector3d x = body.R.col(0);
  EXPECT_NEAR(std::atan2(x.y(), x.x()), 0.5, 0.01);
}

TEST(ClosedLoop, FigureEightAtThreeMetresPerSecond) {
  const FigureEight eight;  // A = 5 m, 3 m/s at the crossing, heading along the velocity
  auto ref = [&](double t) { return eight.at(t); };
  double peak = 0;
  for (double t = 0; t < 20; t += 0.01) peak = std::max(peak, ref(t).v_world_mps.norm());
  ASSERT_NEAR(peak, 3.0, 0.01);
  Se3Controller ctrl;
  RigidBody body;
  body.p = ref(0).p_world_m;
  body.v = ref(0).v_world_mps;
  body.R = flatAttitude(ref(0).a_world_mps2, ref(0).j_world_mps3, ref(0).yaw_rad,
                        ref(0).yaw_rate_radps, 9.81)
               .R_world_body;
  const double period = eight.period();
  double max_err = 0;
  const double rms = fly(
      ctrl, body, ref, period + 1.0, 1.0, [](double, RigidBody&) {}, &max_err);
  RecordProperty("rms_error_m", std::to_string(rms));
  EXPECT_LT(rms, 0.10);
  EXPECT_LT(max_err, 0.2);

  // Without feedforward the same loop is markedly worse: the feedforward is doing its job.
  Se3ControllerConfig no_ff;
  no_ff.use_feedforward = false;
  Se3Controller ctrl2(no_ff);
  RigidBody body2 = RigidBody();
  body2.p = ref(0).p_world_m;
  body2.v = ref(0).v_world_mps;
  const double rms2 = fly(ctrl2, body2, ref, period + 1.0, 1.0, [](double, RigidBody&) {});
  EXPECT_GT(rms2, 2.0 * rms);
}

TEST(ClosedLoop, RecoversFromAVelocityKick) {
  Se3Controller ctrl;
  RigidBody body;
  const Eigen::Vector3d target(0, 0, 1);
  auto ref = [&](double t) {
    FlatReference r;
    r.stamp_s = t;
    r.p_world_m = target;
    return r;
  };
  bool kicked = false;
  double max_err = 0;
  fly(ctrl, body, ref, 1.0, 0.0, [](double, RigidBody&) {});
  auto kick = [&](double t, RigidBody& b) {
    if (!kicked && t >= 0.0) {
      b.v += Eigen::Vector3d(1.0 / std::sqrt(2.0), 1.0 / std::sqrt(2.0), 0);  // 1 m/s sideways
      kicked = true;
    }
  };
  fly(ctrl, body, ref, 4.0, 0.0, kick, &max_err);
  EXPECT_TRUE(kicked);
  EXPECT_GT(max_err, 0.05);  // the kick did displace it
  EXPECT_LT(max_err, 0.5);   // but not far
  EXPECT_LT((body.p - target).norm(), 0.02);
  EXPECT_LT(body.v.norm(), 0.05);
}

TEST(ClosedLoop, StaleOdometryHoldsThenDescendsSlowlyAndLevel) {
  Se3Controller ctrl(brakeOnly());
  RigidBody body;
  body.p = Eigen::Vector3d(0, 0, 5);
  const auto& cfg = ctrl.config();
  OdometryState frozen;
  bool frozen_set = false;
  FlatReference r;
  r.p_world_m = body.p;
  const double end_s = 4.0 + cfg.descent_delay_s;
  for (double t = 0; t < end_s; t += 0.01) {
    r.stamp_s = t;
    OdometryState o = body.odom(t);
    if (t >= 1.0) {  // odometry stops updating
      if (!frozen_set) {
        frozen = o;
        frozen_set = true;
      }
      o = frozen;
    }
    const auto out = ctrl.update(o, r, t);
    for (int k = 0; k < 20; ++k) body.step(out.so3, 0.0005);
    // Before the descent delay has passed the height is held.
    if (t < 1.0 + cfg.odom_timeout_s + cfg.descent_delay_s - 0.05) {
      EXPECT_NEAR(body.p.z(), 5.0, 0.1) << "t = " << t;
    }
  }
  EXPECT_LT(body.v.z(), -0.3);
  EXPECT_GT(body.v.z(), -cfg.descent_speed_mps - 0.1);
  EXPECT_LT(body.v.head<2>().norm(), 0.05);
  EXPECT_GT(body.R(2, 2), 0.999);
}

}  // namespace
}  // namespace efs::control

namespace efs::control {
namespace {

// Odometry lost at 4 m/s: the open-loop brake stops the vehicle within about v^2 / 2a of where
// the last odometry was, instead of drifting on at the last velocity.
TEST(ClosedLoop, StaleOdometryInFastFlightBrakesToAStop) {
  Se3Controller ctrl(brakeOnly());
  const auto& cfg = ctrl.config();
  RigidBody body;
  body.p = Eigen::Vector3d(0, 0, 5);
  body.v = Eigen::Vector3d(4.0, 0, 0);
  OdometryState frozen;
  bool frozen_set = false;
  FlatReference r;
  for (double t = 0; t < 4.0; t += 0.01) {
    r.stamp_s = t;
    r.p_world_m = Eigen::Vector3d(4.0 * t, 0, 5);
    r.v_world_mps = Eigen::Vector3d(4.0, 0, 0);
    OdometryState o = body.odom(t);
    if (t >= 0.5) {
      if (!frozen_set) {
        frozen = o;
        frozen_set = true;
      }
      o = frozen;
    }
    const auto out = ctrl.update(o, r, t);
    for (int k = 0; k < 20; ++k) body.step(out.so3, 0.0005);
  }
  ASSERT_TRUE(frozen_set);
  const double stop_m = 16.0 / (2.0 * cfg.brake_accel_mps2);
  // Plus 4 m/s over the odometry timeout and over the attitude lag, plus slack; drifting on would
  // have covered 14 m.
  const double bound_m = stop_m + 4.0 * (cfg.odom_timeout_s + cfg.brake_attitude_lag_s) + 0.5;
  EXPECT_LT(body.p.x() - frozen.p_world_m.x(), bound_m);
  EXPECT_LT(body.v.head<2>().norm(), 0.3);
  EXPECT_GT(body.R(2, 2), 0.999);  // level again
}

}  // namespace
}  // namespace efs::control

namespace efs::control {
namespace {

// A reference along a circle of radius R at z = 2 m: speed v0 until t_loss, then slowing
// linearly to rest within stop_s (what minco_traj serves when odometry is lost on a curve).
FlatReference curvingStop(double R, double v0, double t_loss, double stop_s, double t) {
  double s = v0 * t, sd = v0, sdd = 0.0;
  if (t > t_loss) {
    const double d = std::min(t - t_loss, stop_s);
    s = v0 * t_loss + v0 * d - 0.5 * v0 / stop_s * d * d;
    sd = v0 * (1.0 - d / stop_s);
    sdd = t - t_loss < stop_s ? -v0 / stop_s : 0.0;
  }
  const double th = s / R;
  const Eigen::Vector3d T(-std::sin(th), std::cos(th), 0), N(-std::cos(th), -std::sin(th), 0);
  FlatReference r;
  r.stamp_s = t;
  r.p_world_m = Eigen::Vector3d(R * std::cos(th), R * std::sin(th), 2.0);
  r.v_world_mps = sd * T;
  r.a_world_mps2 = sdd * T + sd * sd / R * N;
  return r;
}

struct CurvingStopRun {
  double max_error_m = 0.0;
  double final_speed_mps = 0.0;
  bool feed_forward_after_timeout = true;  ///< every step past the odometry timeout
};

// Flies curvingStop(5 m, 3 m/s, loss at 1 s, stop in 1.5 s) with the odometry frozen from the
// loss on; with_imu feeds the body's true acceleration to the controller at 100 Hz, delivered
// in bursts of imu_burst samples (1: each on time; more: late, as on a loaded computer).
CurvingStopRun flyCurvingStopOnFrozenOdometry(const Se3ControllerConfig& cfg, bool with_imu,
                                              int imu_burst = 1) {
  const double R = 5.0, v0 = 3.0, t_loss = 1.0, stop_s = 1.5;
  Se3Controller ctrl(cfg);
  RigidBody body;
  body.p = curvingStop(R, v0, t_loss, stop_s, 0.0).p_world_m;
  body.v = curvingStop(R, v0, t_loss, stop_s, 0.0).v_world_mps;
  CurvingStopRun run;
  OdometryState frozen;
  bool frozen_set = false;
  std::vector<std::pair<Eigen::Vector3d, double>> imu_pending;
  for (double t = 0; t < t_loss + stop_s + 1.0; t += 0.01) {
    const FlatReference r = curvingStop(R, v0, t_loss, stop_s, t);
    OdometryState o = body.odom(t);
    if (t >= t_loss) {
      if (!frozen_set) {
        frozen = o;
        frozen_set = true;
      }
      o = frozen;
    }
    const auto out = ctrl.update(o, r, t);
    if (t > t_loss + ctrl.config().odom_timeout_s && out.mode != ControlMode::kFeedForward)
      run.feed_forward_after_timeout = false;
    const Eigen::Vector3d v_before = body.v;
    for (int k = 0; k < 20; ++k) body.step(out.so3, 0.0005);
    if (with_imu) imu_pending.emplace_back((body.v - v_before) / 0.01, t + 0.01);
    if (static_cast<int>(imu_pending.size()) >= imu_burst) {
      for (const auto& [a, stamp] : imu_pending) ctrl.observeImu(a, stamp);
      imu_pending.clear();
    }
    run.max_error_m = std::max(run.max_error_m, (body.p - r.p_world_m).norm());
  }
  run.final_speed_mps = body.v.norm();
  return run;
}

// Odometry lost on a curve: the reference (as minco_traj serves it then) slows to a stop along
// a 5 m-radius arc; followed feed-forward only, the vehicle stays on the arc.
TEST(ClosedLoop, LostOdometryFollowsACurvingStopOpenLoop) {
  Se3ControllerConfig cfg;
  cfg.dead_reckoning_lag_s = 0.05;  // this rigid body's attitude loop (marsim's is slower)
  const CurvingStopRun run = flyCurvingStopOnFrozenOdometry(cfg, false);
  EXPECT_TRUE(run.feed_forward_after_timeout);
  EXPECT_LT(run.max_error_m, 0.3);
  EXPECT_LT(run.final_speed_mps, 0.3);
  // A straight-line brake from the loss point would have left the arc by more than a metre.
}

}  // namespace
}  // namespace efs::control

namespace efs::control {
namespace {

// The same curving stop with an IMU: integrating measured accelerations, dead reckoning no
// longer depends on the lag model (set far off here) and the vehicle stays on the arc.
TEST(ClosedLoop, LostOdometryWithAnImuFollowsTheStopDespiteAWrongLagModel) {
  Se3ControllerConfig cfg;
  cfg.dead_reckoning_lag_s = 0.6;  // badly wrong on purpose
  const double worst[2] = {flyCurvingStopOnFrozenOdometry(cfg, false).max_error_m,
                           flyCurvingStopOnFrozenOdometry(cfg, true).max_error_m};
  EXPECT_LT(worst[1], 0.3);       // with the IMU
  EXPECT_GT(worst[0], worst[1]);  // without it the wrong lag model shows
}

// The same with the IMU samples arriving late, eight at a time (80 ms bursts, longer than
// imu_max_age_s, so the wrong lag model fills the gaps): each burst is integrated sample by
// sample from the last odometry, which undoes what the model got wrong meanwhile.
TEST(ClosedLoop, LostOdometryWithLateImuBurstsStillFollowsTheStop) {
  Se3ControllerConfig cfg;
  cfg.dead_reckoning_lag_s = 0.6;  // badly wrong on purpose
  const CurvingStopRun bursts = flyCurvingStopOnFrozenOdometry(cfg, true, 8);
  const CurvingStopRun model_only = flyCurvingStopOnFrozenOdometry(cfg, false);
  EXPECT_LT(bursts.max_error_m, 0.3);
  EXPECT_LT(bursts.final_speed_mps, 0.3);
  EXPECT_LT(bursts.max_error_m, 0.5 * model_only.max_error_m);
}

}  // namespace
}  // namespace efs::control
