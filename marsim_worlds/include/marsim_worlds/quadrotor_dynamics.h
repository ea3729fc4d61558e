// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Rigid-body quadrotor with the inner loop of a flight controller, the way MARSIM's so3
// simulator is driven: a command (SO3Command-like force + attitude, or AttitudeTarget-like
// attitude + body rates + normalised thrust) is turned into collective thrust and body torques
// by a geometric attitude controller (Lee et al. 2010), the rotors follow with a first-order lag,
// and the body integrates with RK4 and quaternion renormalisation. World frame ENU, z up;
// body frame FLU (REP 103).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace efs::sim {

struct QuadrotorConfig {
  double mass_kg = 0.98;
  Eigen::Vector3d inertia_diag_kg_m2 = Eigen::Vector3d(2.64e-3, 2.64e-3, 4.96e-3);
  double gravity_m_s2 = 9.81;
  /// Linear aerodynamic drag force = -coefficient * v_world.
  double linear_drag_N_s_per_m = 0.05;
  /// First-order lag of thrust and torques behind the controller (rotor spin-up).
  double rotor_time_constant_s = 0.02;
  double max_thrust_N = 25.0;
  double min_thrust_N = 0.0;
  double max_torque_Nm = 0.5;         ///< Per body axis.
  double max_body_rate_rad_s = 10.0;  ///< Per body axis, the flight controller's rate limit.
  /// Normalised thrust (AttitudeTarget.thrust in [0, 1]) that holds hover.
  double hover_thrust_normalized = 0.5;
  /// Attitude gains of the inner loop used for attitude targets (SO3 commands bring their own).
  Eigen::Vector3d attitude_kR_Nm_per_rad = Eigen::Vector3d(1.5, 1.5, 1.0);
  Eigen::Vector3d attitude_kOm_Nm_s_per_rad = Eigen::Vector3d(0.13, 0.13, 0.1);

  void validate() const;  ///< Throws efs::ConfigError naming the key.
};

struct QuadrotorState {
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world_m_s = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
  Eigen::Vector3d omega_body_rad_s = Eigen::Vector3d::Zero();
  double thrust_N = 0.0;                                     ///< Actual (lagged) collective thrust.
  Eigen::Vector3d torque_body_Nm = Eigen::Vector3d::Zero();  ///< Actual (lagged) torques.
};

/// Like quadrotor_msgs/SO3Command: desired force in the world frame, desired orientation, the
/// attitude gains, and (an extension MARSIM's so3 control uses internally) a desired body rate.
struct SO3Command {
  Eigen::Vector3d force_world_N = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_world_body_des = Eigen::Quaterniond::Identity();
  Eigen::Vector3d omega_body_des_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d kR_Nm_per_rad = Eigen::Vector3d(1.5, 1.5, 1.0);
  Eigen::Vector3d kOm_Nm_s_per_rad = Eigen::Vector3d(0.13, 0.13, 0.1);
};

/// Like mavros_msgs/AttitudeTarget.
struct AttitudeTargetCommand {
  static constexpr uint8_t kIgnoreRollRate = 1, kIgnorePitchRate = 2, kIgnoreYawRate = 4,
                           kIgnoreThrust = 64, kIgnoreAttitude = 128;
  uint8_t type_mask = 0;
  Eigen::Quaterniond q_world_body_des = Eigen::Quaterniond::Identity();
  Eigen::Vector3d body_rate_des_rad_s = Eigen::Vector3d::Zero();
  double thrust_normalized = 0.5;  ///< [0, 1]; hover at QuadrotorConfig::hover_thrust_normalized.
};

/// Result of handing a command over: rejected commands leave the previous one in force.
struct CommandStatus {
  bool accepted = true;
  std::string reason;  ///< Why it was rejected (empty if accepted).
};

class QuadrotorDynamics {
 public:
  explicit QuadrotorDynamics(const QuadrotorConfig& config,
                             const QuadrotorState& initial = QuadrotorState());

  const QuadrotorConfig& config() const { return config_; }
  const QuadrotorState& state() const { return state_; }
  void setState(const QuadrotorState& s) { state_ = s; }

  /// Checks and stores the command; NaN/inf values or a zero quaternion are rejected with a
  /// reason and the last valid command (initially: hover at the initial attitude) stays in force.
  CommandStatus setCommand(const SO3Command& cmd);
  CommandStatus setCommand(const AttitudeTargetCommand& cmd);

  /// The command that holds the current attitude's yaw level in hover.
  SO3Command hoverCommand() const;
  /// What an ideal accelerometer on the body measures now: the specific force (thrust and drag
  /// over mass, gravity excluded) in the body frame; [0, 0, g] when hovering.
  Eigen::Vector3d specificForceBody() const;

  /// Advances by `dt_s` (one RK4 step with the controller output held; callers keep dt small,
  /// the simulator uses its physics rate).
  void step(double dt_s);

  /// Controller output for the stored command at the current state (thrust [N], torque [Nm]),
  /// saturated to the configured limits.
  void controlOutput(double* thrust_N, Eigen::Vector3d* torque_body_Nm) const;

 private:
  struct Deriv;
  QuadrotorConfig config_;
  QuadrotorState state_;
  Eigen::Vector3d inertia_;
  // The active command, held as a unified attitude-control target.
  bool attitude_active_ = true;
  double thrust_cmd_N_ = 0.0;
  bool thrust_from_force_ = true;  ///< SO3: thrust = force . body z, evaluated each step.
  Eigen::Vector3d force_world_N_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_des_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d omega_des_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d kR_, kOm_;
};

}  // namespace efs::sim
