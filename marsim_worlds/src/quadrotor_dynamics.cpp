// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/quadrotor_dynamics.h"

#include <algorithm>
#include <cmath>

#include "efs_common/config_check.h"

namespace efs::sim {
namespace {

Eigen::Vector3d vee(const Eigen::Matrix3d& m) { return {m(2, 1), m(0, 2), m(1, 0)}; }

bool finiteQuat(const Eigen::Quaterniond& q) { return q.coeffs().allFinite(); }

/// The attitude with the same heading as `q` and level roll/pitch.
Eigen::Quaterniond yawOnly(const Eigen::Quaterniond& q) {
  const Eigen::Vector3d x = q * Eigen::Vector3d::UnitX();
  const double yaw = std::atan2(x.y(), x.x());
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
}

}  // namespace

void QuadrotorConfig::validate() const {
  requireInRange("mass_kg", mass_kg, 0.01, 100.0);
  for (int i = 0; i < 3; ++i) {
    requireInRange("inertia_diag_kg_m2", inertia_diag_kg_m2[i], 1e-6, 100.0);
    requireInRange("attitude_kR_Nm_per_rad", attitude_kR_Nm_per_rad[i], 0.0, 1e3);
    requireInRange("attitude_kOm_Nm_s_per_rad", attitude_kOm_Nm_s_per_rad[i], 0.0, 1e3);
  }
  requireInRange("gravity_m_s2", gravity_m_s2, 0.0, 30.0);
  requireInRange("linear_drag_N_s_per_m", linear_drag_N_s_per_m, 0.0, 100.0);
  requireInRange("rotor_time_constant_s", rotor_time_constant_s, 1e-3, 1.0);
  requireInRange("max_thrust_N", max_thrust_N, 1e-3, 1e4);
  requireInRange("min_thrust_N", min_thrust_N, 0.0, max_thrust_N);
  requireThat(max_thrust_N > mass_kg * gravity_m_s2, "max_thrust_N",
              "must exceed the weight mass_kg * gravity_m_s2, or the vehicle cannot hover");
  requireInRange("max_torque_Nm", max_torque_Nm, 1e-6, 1e3);
  requireInRange("max_body_rate_rad_s", max_body_rate_rad_s, 0.1, 100.0);
  requireInRange("hover_thrust_normalized", hover_thrust_normalized, 0.05, 1.0);
}

QuadrotorDynamics::QuadrotorDynamics(const QuadrotorConfig& config, const QuadrotorState& initial)
    : config_((config.validate(), config)),
      state_(initial),
      inertia_(config.inertia_diag_kg_m2),
      kR_(config.attitude_kR_Nm_per_rad),
      kOm_(config.attitude_kOm_Nm_s_per_rad) {
  state_.q_world_body.normalize();
  const SO3Command hover = hoverCommand();
  force_world_N_ = hover.force_world_N;
  q_des_ = hover.q_world_body_des;
}

Eigen::Vector3d QuadrotorDynamics::specificForceBody() const {
  const double m = config_.mass_kg;
  return Eigen::Vector3d(0, 0, state_.thrust_N / m) -
         state_.q_world_body.conjugate() *
             ((config_.linear_drag_N_s_per_m / m) * state_.v_world_m_s);
}

SO3Command QuadrotorDynamics::hoverCommand() const {
  SO3Command c;
  c.force_world_N = Eigen::Vector3d(0, 0, config_.mass_kg * config_.gravity_m_s2);
  c.q_world_body_des = yawOnly(state_.q_world_body);
  c.kR_Nm_per_rad = config_.attitude_kR_Nm_per_rad;
  c.kOm_Nm_s_per_rad = config_.attitude_kOm_Nm_s_per_rad;
  return c;
}

CommandStatus QuadrotorDynamics::setCommand(const SO3Command& cmd) {
  if (!cmd.force_world_N.allFinite()) return {false, "SO3Command.force is not finite"};
  if (!finiteQuat(cmd.q_world_body_des)) return {false, "SO3Command.orientation is not finite"};
  if (cmd.q_world_body_des.norm() < 1e-6) return {false, "SO3Command.orientation has zero norm"};
  if (!cmd.omega_body_des_rad_s.allFinite()) {
    return {false, "SO3Command angular velocity is not finite"};
  }
  if (!cmd.kR_Nm_per_rad.allFinite() || (cmd.kR_Nm_per_rad.array() < 0).any()) {
    return {false, "SO3Command.kR must be finite and >= 0"};
  }
  if (!cmd.kOm_Nm_s_per_rad.allFinite() || (cmd.kOm_Nm_s_per_rad.array() < 0).any()) {
    return {false, "SO3Command.kOm must be finite and >= 0"};
  }
  attitude_active_ = true;
  thrust_from_force_ = true;
  force_world_N_ = cmd.force_world_N;
  q_des_ = cmd.q_world_body_des.normalized();
  omega_des_ = cmd.omega_body_des_rad_s;
  kR_ = cmd.kR_Nm_per_rad;
  kOm_ = cmd.kOm_Nm_s_per_rad;
  return {};
}

CommandStatus QuadrotorDynamics::setCommand(const AttitudeTargetCommand& cmd) {
  using A = AttitudeTargetCommand;
  const bool use_attitude = !(cmd.type_mask & A::kIgnoreAttitude);
  const bool use_thrust = !(cmd.type_mask & A::kIgnoreThrust);
  if (use_attitude && !finiteQuat(cmd.q_world_body_des)) {
    return {false, "AttitudeTarget.orientation is not finite"};
  }
  if (use_attitude && cmd.q_world_body_des.norm() < 1e-6) {
    return {false, "AttitudeTarget.orientation has zero norm"};
  }
  if (!cmd.body_rate_des_rad_s.allFinite())
    return {false, "AttitudeTarget.body_rate is not finite"};
  if (use_thrust && !std::isfinite(cmd.thrust_normalized)) {
    return {false, "AttitudeTarget.thrust is not finite"};
  }
  attitude_active_ = use_attitude;
  if (use_attitude) q_des_ = cmd.q_world_body_des.normalized();
  omega_des_ = cmd.body_rate_des_rad_s;
  if (cmd.type_mask & A::kIgnoreRollRate) omega_des_.x() = 0.0;
  if (cmd.type_mask & A::kIgnorePitchRate) omega_des_.y() = 0.0;
  if (cmd.type_mask & A::kIgnoreYawRate) omega_des_.z() = 0.0;
  const double hover_N = config_.mass_kg * config_.gravity_m_s2;
  thrust_from_force_ = false;
  thrust_cmd_N_ = use_thrust ? std::clamp(cmd.thrust_normalized, 0.0, 1.0) /
                                   config_.hover_thrust_normalized * hover_N
                             : hover_N;
  kR_ = config_.attitude_kR_Nm_per_rad;
  kOm_ = config_.attitude_kOm_Nm_s_per_rad;
  return {};
}

void QuadrotorDynamics::controlOutput(double* thrust_N, Eigen::Vector3d* torque_body_Nm) const {
  const Eigen::Matrix3d R = state_.q_world_body.toRotationMatrix();
  const Eigen::Vector3d& w = state_.omega_body_rad_s;
  const Eigen::Vector3d Jw = inertia_.cwiseProduct(w);
  Eigen::Vector3d tau;
  if (attitude_active_) {
    const Eigen::Matrix3d Rd = q_des_.toRotationMatrix();
    const Eigen::Vector3d eR = 0.5 * vee(Rd.transpose() * R - R.transpose() * Rd);
    const Eigen::Vector3d eOm = w - R.transpose() * Rd * omega_des_;
    tau = -kR_.cwiseProduct(eR) - kOm_.cwiseProduct(eOm) + w.cross(Jw);
  } else {
    tau = -kOm_.cwiseProduct(w - omega_des_) + w.cross(Jw);
  }
  const double T = thrust_from_force_ ? force_world_N_.dot(R.col(2)) : thrust_cmd_N_;
  *thrust_N = std::clamp(T, config_.min_thrust_N, config_.max_thrust_N);
  *torque_body_Nm = tau.cwiseMax(-config_.max_torque_Nm).cwiseMin(config_.max_torque_Nm);
}

struct QuadrotorDynamics::Deriv {
  Eigen::Vector3d dp, dv;
  Eigen::Vector4d dq;  // quaternion coefficients (x, y, z, w)
  Eigen::Vector3d dw;
  double dT;
  Eigen::Vector3d dtau;
};

void QuadrotorDynamics::step(double dt_s) {
  if (!(dt_s > 0.0)) return;
  double T_cmd;
  Eigen::Vector3d tau_cmd;
  controlOutput(&T_cmd, &tau_cmd);

  const double m = config_.mass_kg, g = config_.gravity_m_s2;
  const double drag = config_.linear_drag_N_s_per_m, tc = config_.rotor_time_constant_s;
  const Eigen::Vector3d J = inertia_;
  auto f = [&](const QuadrotorState& s) {
    Deriv d;
    const Eigen::Quaterniond q = s.q_world_body.normalized();
    d.dp = s.v_world_m_s;
    d.dv = q * Eigen::Vector3d(0, 0, s.thrust_N / m) - Eigen::Vector3d(0, 0, g) -
           (drag / m) * s.v_world_m_s;
    const Eigen::Quaterniond w(0.0, s.omega_body_rad_s.x(), s.omega_body_rad_s.y(),
                               s.omega_body_rad_s.z());
    d.dq = 0.5 * (s.q_world_body * w).coeffs();
    const Eigen::Vector3d& om = s.omega_body_rad_s;
    d.dw = (s.torque_body_Nm - om.cross(J.cwiseProduct(om))).cwiseQuotient(J);
    d.dT = (T_cmd - s.thrust_N) / tc;
    d.dtau = (tau_cmd - s.torque_body_Nm) / tc;
    return d;
  };
  auto add = [](const QuadrotorState& s, const Deriv& d, double h) {
    QuadrotorState r = s;
    r.p_world_m += h * d.dp;
    r.v_world_m_s += h * d.dv;
    r.q_world_body.coeffs() += h * d.dq;
    r.omega_body_rad_s += h * d.dw;
    r.thrust_N += h * d.dT;
    r.torque_body_Nm += h * d.dtau;
    return r;
  };
  const QuadrotorState& s0 = state_;
  const Deriv k1 = f(s0);
  const Deriv k2 = f(add(s0, k1, 0.5 * dt_s));
  const Deriv k3 = f(add(s0, k2, 0.5 * dt_s));
  const Deriv k4 = f(add(s0, k3, dt_s));
  Deriv sum;
  sum.dp = k1.dp + 2 * k2.dp + 2 * k3.dp + k4.dp;
  sum.dv = k1.dv + 2 * k2.dv + 2 * k3.dv + k4.dv;
  sum.dq = k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq;
  sum.dw = k1.dw + 2 * k2.dw + 2 * k3.dw + k4.dw;
  sum.dT = k1.dT + 2 * k2.dT + 2 * k3.dT + k4.dT;
  sum.dtau = k1.dtau + 2 * k2.dtau + 2 * k3.dtau + k4.dtau;
  state_ = add(s0, sum, dt_s / 6.0);
  state_.q_world_body.normalize();
  // The flight controller's rate limit, applied as a saturation of the body rates.
  const double wmax = config_.max_body_rate_rad_s;
  state_.omega_body_rad_s = state_.omega_body_rad_s.cwiseMax(-wmax).cwiseMin(wmax);
}

}  // namespace efs::sim
