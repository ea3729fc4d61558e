// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Closed loop of Se3Controller with the suite simulator's quadrotor (marsim_worlds'
// QuadrotorDynamics: inner attitude loop, rotor lag, drag, RK4), as marsim_node runs it:
// controller at 100 Hz on true-state odometry, physics at 500 Hz, the command held in between.
// Shared by sim_closed_loop_test and bench/control_bench.
#pragma once

#include <algorithm>
#include <cmath>

#include "marsim_worlds/quadrotor_dynamics.h"
#include "se3_controller/se3_controller.h"

namespace efs::control::testing {

enum class Output { kSo3, kAttitudeTarget };

struct SimFlight {
  double rms_error_m = 0.0;  ///< position error RMS over [settle, duration)
  double max_error_m = 0.0;
  ControlMode last_mode = ControlMode::kNoOdometry;
};

inline OdometryState odometryOf(const sim::QuadrotorState& s, double t_s,
                                const Eigen::Vector3d& a_world_mps2) {
  OdometryState o;
  o.stamp_s = t_s;
  o.p_world_m = s.p_world_m;
  o.v_world_mps = s.v_world_m_s;
  o.q_world_body = s.q_world_body;
  o.omega_body_radps = s.omega_body_rad_s;
  o.has_acceleration = true;
  o.a_world_mps2 = a_world_mps2;
  return o;
}

inline void applyCommand(const ControlOutput& out, Output output, sim::QuadrotorDynamics& quad) {
  if (output == Output::kSo3) {
    sim::SO3Command c;
    c.force_world_N = out.so3.force_world_N;
    c.q_world_body_des = out.so3.orientation;
    c.omega_body_des_rad_s = out.so3.angular_velocity_body_radps;
    c.kR_Nm_per_rad = out.so3.kR;
    c.kOm_Nm_s_per_rad = out.so3.kOm;
    quad.setCommand(c);
  } else {
    sim::AttitudeTargetCommand c;
    c.type_mask = out.attitude.type_mask;
    c.q_world_body_des = out.attitude.orientation;
    c.body_rate_des_rad_s = out.attitude.body_rate_radps;
    c.thrust_normalized = out.attitude.thrust;
    quad.setCommand(c);
  }
}

/// Flies `ref_at(t)` for duration_s from the quadrotor's current state (time starts at t0_s);
/// `hook(t, quad)` may disturb the vehicle before each control step.
template <typename RefFn, typename Hook>
SimFlight flySim(Se3Controller& ctrl, sim::QuadrotorDynamics& quad, RefFn ref_at, double t0_s,
                 double duration_s, double settle_s, Output output, Hook hook) {
  const double dt_ctrl = 0.01;
  const int substeps = 5;  // 500 Hz physics
  SimFlight f;
  double sum = 0.0;
  int n = 0;
  Eigen::Vector3d a_world = Eigen::Vector3d::Zero();
  const int steps = static_cast<int>(std::lround(duration_s / dt_ctrl));
  for (int k = 0; k < steps; ++k) {
    const double t = t0_s + k * dt_ctrl;
    hook(t, quad);
    const ControlOutput out = ctrl.update(odometryOf(quad.state(), t, a_world), ref_at(t), t);
    f.last_mode = out.mode;
    applyCommand(out, output, quad);
    const Eigen::Vector3d v0 = quad.state().v_world_m_s;
    for (int s = 0; s < substeps; ++s) quad.step(dt_ctrl / substeps);
    a_world = (quad.state().v_world_m_s - v0) / dt_ctrl;
    if (t - t0_s >= settle_s) {
      const double e = (quad.state().p_world_m - ref_at(t + dt_ctrl).p_world_m).norm();
      sum += e * e;
      ++n;
      f.max_error_m = std::max(f.max_error_m, e);
    }
  }
  f.rms_error_m = std::sqrt(sum / std::max(1, n));
  return f;
}

/// The quadrotor at rest in the reference's flat state at t (position, velocity, attitude).
inline sim::QuadrotorState stateOnReference(const FlatReference& r, double gravity_mps2) {
  sim::QuadrotorState s;
  s.p_world_m = r.p_world_m;
  s.v_world_m_s = r.v_world_mps;
  const FlatAttitude fa =
      flatAttitude(r.a_world_mps2, r.j_world_mps3, r.yaw_rad, r.yaw_rate_radps, gravity_mps2);
  s.q_world_body = Eigen::Quaterniond(fa.R_world_body);
  s.omega_body_rad_s = fa.omega_body_radps;
  return s;
}

}  // namespace efs::control::testing
