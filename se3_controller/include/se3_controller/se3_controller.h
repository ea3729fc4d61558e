// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Geometric tracking on SE(3) (Lee, Leok, McClamroch, CDC 2010) with differential-flatness
// feedforward (Mellinger & Kumar 2011; Faessler et al. 2018), for the paper's Sec. VIII-A flight
// stack. The outer loop turns position/velocity errors and the reference acceleration into the
// desired thrust vector; the desired attitude takes its z axis from that vector and its heading
// from the reference yaw (b1c = [cos yaw, sin yaw, 0], b2 = b3 x b1c / |.|, b1 = b2 x b3); the
// desired body rates come from the reference jerk and yaw rate. Two outputs:
//   * SO3Command (MARSIM / so3 simulator, quadrotor_msgs field for field): world force, desired
//     orientation, attitude gains kR / kOm for the simulator's inner loop, plus the desired body
//     rates (not carried by quadrotor_msgs/SO3Command; kept for inner loops that accept it);
//   * AttitudeTarget (PX4 through mavros): orientation, body rates and normalised thrust, scaled
//     by an online hover-throttle estimate.
// Safety (time is injected; nothing here reads a clock):
//   * odometry with NaN/Inf is rejected (reason given) and the last valid odometry is used;
//   * odometry older than odom_timeout_s -> level attitude, gentle open-loop descent;
//   * reference older than command_timeout_s, or with NaN/Inf -> hover at the position latched
//     when the reference was lost.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <deque>
#include <optional>
#include <string>

namespace efs::control {

/// Flat-output reference (what minco_traj's sampler or a PositionCommand provides).
struct FlatReference {
  double stamp_s = 0.0;
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_world_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d j_world_mps3 = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
  double yaw_rate_radps = 0.0;
};

struct OdometryState {
  double stamp_s = 0.0;
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world_mps = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
  Eigen::Vector3d omega_body_radps = Eigen::Vector3d::Zero();
  /// Measured acceleration (world frame, gravity removed: zero when hovering), for the hover
  /// throttle estimate; ignored unless has_acceleration.
  bool has_acceleration = false;
  Eigen::Vector3d a_world_mps2 = Eigen::Vector3d::Zero();
};

struct Se3ControllerConfig {
  double mass_kg = 0.98;
  double gravity_mps2 = 9.81;
  Eigen::Vector3d kp_position = Eigen::Vector3d(6.0, 6.0, 8.0);  ///< [1/s^2]
  Eigen::Vector3d kv_velocity = Eigen::Vector3d(4.0, 4.0, 5.0);  ///< [1/s]
  double max_position_error_m = 1.5;  ///< feedback saturation (large errors fly at bounded acc.)
  double max_tilt_rad = 0.7;
  double min_thrust_accel_mps2 = 2.0;  ///< never command less collective acceleration
  /// Inner-loop gains handed to the simulator (SO3Command kR / kOm).
  Eigen::Vector3d kR = Eigen::Vector3d(1.5, 1.5, 1.0);
  Eigen::Vector3d kOm = Eigen::Vector3d(0.13, 0.13, 0.1);
  bool use_feedforward = true;  ///< reference acceleration and jerk/yaw-rate body rates
  // Safety.
  double odom_timeout_s = 0.2;
  double command_timeout_s = 0.5;
  /// Odometry lost while the reference is still fresh (minco_traj then stops it along its
  /// checked path): follow it feed-forward only, from where the vehicle last was on it, for at
  /// most this long. 0 = never (straight to the brake below).
  double feedforward_on_odometry_loss_s = 5.0;
  /// Meanwhile the state is dead-reckoned from the commanded acceleration, which the vehicle
  /// reaches with this first-order lag (attitude loop), and fed back as odometry would be.
  double dead_reckoning_lag_s = 0.15;
  /// An IMU acceleration (observeImu) younger than this is integrated instead of that model.
  double imu_max_age_s = 0.05;
  /// Odometry lost without a usable reference: first brake open-loop against the last measured
  /// horizontal velocity at this deceleration (dead reckoning, as a flight controller's failsafe
  /// would), so that a vehicle at 4 m/s stops within about 2 m instead of drifting on; 0 = no
  /// braking.
  double brake_accel_mps2 = 4.0;
  /// The tilt builds up and relaxes over the attitude loop's response time, so the brake is held
  /// this much longer than |v| / brake_accel to take out the speed lost meanwhile.
  double brake_attitude_lag_s = 0.15;
  /// After the brake the vehicle holds its height this long before the gentle descent starts: a
  /// LIO stall of a few seconds (degenerate geometry) must not put it on a cave floor (seen).
  double descent_delay_s = 3.0;
  double descent_accel_mps2 = 0.5;  ///< open-loop descent: accelerate down at this ...
  double descent_speed_mps = 0.5;   ///< ... until this speed, then hold the thrust at hover
  // Hover throttle (normalised thrust in [0, 1] that holds the vehicle at 1 g).
  double hover_throttle_initial = 0.5;
  double hover_throttle_min = 0.1;
  double hover_throttle_max = 0.9;
  double hover_estimator_time_constant_s = 1.0;
  void validate() const;
};

/// Fields of quadrotor_msgs/SO3Command (+ AuxCommand), ROS-free.
struct So3CommandOut {
  Eigen::Vector3d force_world_N = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d angular_velocity_body_radps = Eigen::Vector3d::Zero();
  Eigen::Vector3d kR = Eigen::Vector3d::Zero();
  Eigen::Vector3d kOm = Eigen::Vector3d::Zero();
  double current_yaw_rad = 0.0;
  double kf_correction = 0.0;
  double angle_corrections[2] = {0.0, 0.0};
  bool enable_motors = true;
  bool use_external_yaw = false;
};

/// Fields of mavros_msgs/AttitudeTarget, ROS-free.
struct AttitudeTargetOut {
  uint8_t type_mask = 0;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d body_rate_radps = Eigen::Vector3d::Zero();
  double thrust = 0.0;  ///< normalised [0, 1]
};

enum class ControlMode {
  kTracking,      ///< following the reference
  kHoldPosition,  ///< reference stale or invalid: hovering at the latched position
  kFeedForward,   ///< odometry stale, reference fresh: following it on a dead-reckoned state
  kLevelDescend,  ///< odometry stale: brake against the last velocity, level, hold, then descend
  kNoOdometry     ///< nothing valid received yet: motors idle (the ROS node sends nothing)
};
const char* toString(ControlMode m);

struct ControlOutput {
  ControlMode mode = ControlMode::kNoOdometry;
  std::string reason;              ///< why the mode is not kTracking (empty when tracking)
  bool odometry_rejected = false;  ///< this call's odometry was invalid and ignored
  So3CommandOut so3;
  AttitudeTargetOut attitude;
  Eigen::Vector3d position_error_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_error_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d attitude_error = Eigen::Vector3d::Zero();    ///< e_R = vee(Rd^T R - R^T Rd)/2
  Eigen::Vector3d rate_error_radps = Eigen::Vector3d::Zero();  ///< Omega - R^T Rd Omega_d
  double collective_thrust_N = 0.0;                            ///< thrust along the current body z
};

/// Attitude, body rates and mass-normalised collective thrust from a flat reference (no
/// feedback): the differential-flatness map. thrust_accel_world = a + g e3.
struct FlatAttitude {
  Eigen::Matrix3d R_world_body = Eigen::Matrix3d::Identity();
  Eigen::Vector3d omega_body_radps = Eigen::Vector3d::Zero();
  double thrust_accel_mps2 = 0.0;
};
/// Attitude from a thrust direction and yaw (Lee's construction); the thrust vector must not be
/// horizontal-parallel to the heading (handled by falling back to the previous y axis).
Eigen::Matrix3d attitudeFromThrust(const Eigen::Vector3d& thrust_dir_world, double yaw_rad);
/// Body rates of that attitude for a thrust vector changing at `thrust_rate` (= jerk for the
/// flat map) and a yaw changing at `yaw_rate`.
Eigen::Vector3d bodyRatesFromJerk(const Eigen::Matrix3d& R, const Eigen::Vector3d& thrust_vec,
                                  const Eigen::Vector3d& thrust_rate, double yaw_rad,
                                  double yaw_rate_radps);
FlatAttitude flatAttitude(const Eigen::Vector3d& a_world_mps2, const Eigen::Vector3d& j_world_mps3,
                          double yaw_rad, double yaw_rate_radps, double gravity_mps2);

class Se3Controller {
 public:
  explicit Se3Controller(const Se3ControllerConfig& cfg = {});
  const Se3ControllerConfig& config() const { return cfg_; }

  /// One control step at time now_s (same clock as the stamps). Throws std::invalid_argument if
  /// now_s is not finite (a broken contract, not a sensor fault). `ref` is empty until a
  /// reference has arrived: the vehicle then holds where it is. (A placeholder reference "at the
  /// origin, stamped 0" would count as fresh for command_timeout_s after a simulated clock
  /// starts; seen on a loaded machine: a vehicle hovering at 10 m dived 2.4 m into the floor.)
  ControlOutput update(const OdometryState& odom, const std::optional<FlatReference>& ref,
                       double now_s);
  /// Feeds one acceleration measurement to the hover-throttle estimate (the last commanded
  /// normalised thrust and the attitude are remembered from update()).
  void observeAcceleration(const Eigen::Vector3d& a_world_mps2,
                           const Eigen::Quaterniond& q_world_body, double dt_s);
  double hoverThrottle() const { return hover_throttle_; }
  /// One IMU acceleration (world frame, gravity removed) at stamp_s (the clock of update()).
  /// Dead reckoning through an odometry loss integrates every sample since the last odometry,
  /// each over the interval it ends, from the last odometry state on every control step: samples
  /// that arrive late or in bursts (a loaded onboard computer) still count, and in full.
  void observeImu(const Eigen::Vector3d& a_world_mps2, double stamp_s);
  void reset();

 private:
  ControlOutput track(const OdometryState& odom, const FlatReference& ref, bool feedforward);
  ControlOutput levelDescend(double now_s);
  void fillOutputs(const OdometryState& odom, const Eigen::Vector3d& thrust_accel_world,
                   double yaw_rad, const Eigen::Vector3d& omega_d, ControlOutput& out);

  Se3ControllerConfig cfg_;
  bool have_odom_ = false;
  OdometryState last_odom_;
  bool holding_ = false;
  Eigen::Vector3d hold_position_ = Eigen::Vector3d::Zero();
  double hold_yaw_ = 0.0;
  bool descending_ = false;
  // Dead reckoning while odometry is stale (kFeedForward).
  bool reckoning_ = false;
  double reckoning_stamp_s_ = 0.0;
  Eigen::Vector3d reckoned_p_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d reckoned_v_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d reckoned_a_ = Eigen::Vector3d::Zero();  ///< lagged commanded acceleration
  Eigen::Vector3d last_accel_cmd_ = Eigen::Vector3d::Zero();
  bool have_imu_ = false;
  double imu_stamp_s_ = 0.0;
  Eigen::Vector3d imu_accel_world_ = Eigen::Vector3d::Zero();
  struct ImuSample {
    double stamp_s;
    Eigen::Vector3d a_world_mps2;
  };
  /// Samples newer than the last odometry, in stamp order (bounded: kMaxImuSamples).
  std::deque<ImuSample> imu_samples_;
  static constexpr size_t kMaxImuSamples = 4000;
  double descent_start_s_ = 0.0;
  Eigen::Vector2d brake_velocity_mps_ = Eigen::Vector2d::Zero();  ///< at the onset of the descent
  double hover_throttle_ = 0.5;
  double last_thrust_cmd_ = 0.0;
  double last_acc_stamp_s_ = 0.0;
  bool have_acc_stamp_ = false;
};

}  // namespace efs::control
