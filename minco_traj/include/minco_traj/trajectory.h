// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Piecewise polynomial position trajectory (quintic pieces, world frame) plus an optional yaw
// profile, and the sampler that the trajectory server and the controller reference use.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace efs::traj {

/// Coefficients of one position piece: column k multiplies t^k (t local to the piece, seconds).
using PieceCoeffs = Eigen::Matrix<double, 3, 6>;

/// One flat-output sample: everything the controller's feedforward needs.
struct TrajectoryPoint {
  double t_s = 0.0;
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_world_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d j_world_mps3 = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
  double yaw_rate_radps = 0.0;
  double yaw_acc_radps2 = 0.0;
};

/// Yaw as piecewise quadratic segments (constant yaw acceleration per segment), which is what a
/// rate- and acceleration-limited profile needs; after the last segment yaw is held.
struct YawSegment {
  double duration_s = 0.0;
  double yaw0_rad = 0.0;
  double rate0_radps = 0.0;
  double acc_radps2 = 0.0;
};

class YawProfile {
 public:
  YawProfile() = default;
  explicit YawProfile(double constant_yaw_rad) : hold_yaw_rad_(constant_yaw_rad) {}
  void addSegment(const YawSegment& s);
  /// Yaw, rate and acceleration at t (clamped to [0, inf); held after the end). Yaw is unwrapped.
  void sample(double t_s, double* yaw_rad, double* rate_radps, double* acc_radps2) const;
  double duration() const;
  const std::vector<YawSegment>& segments() const { return segments_; }

 private:
  std::vector<YawSegment> segments_;
  double hold_yaw_rad_ = 0.0;
};

class Trajectory {
 public:
  Trajectory() = default;
  Trajectory(std::vector<PieceCoeffs> pieces, std::vector<double> durations_s);

  int pieceCount() const { return static_cast<int>(pieces_.size()); }
  bool empty() const { return pieces_.empty(); }
  double duration() const { return total_s_; }
  const std::vector<PieceCoeffs>& pieces() const { return pieces_; }
  const std::vector<double>& durations() const { return durations_s_; }

  /// Piece index and local time for global t (clamped to [0, duration]).
  int locate(double t_s, double* local_t_s) const;
  Eigen::Vector3d derivative(double t_s, int order) const;
  Eigen::Vector3d position(double t_s) const { return derivative(t_s, 0); }
  Eigen::Vector3d velocity(double t_s) const { return derivative(t_s, 1); }
  Eigen::Vector3d acceleration(double t_s) const { return derivative(t_s, 2); }
  Eigen::Vector3d jerk(double t_s) const { return derivative(t_s, 3); }

  void setYaw(const YawProfile& yaw) { yaw_ = yaw; }
  const YawProfile& yaw() const { return yaw_; }

  /// Full sample (p, v, a, jerk, yaw, yaw rate). Beyond the end the final state is held with zero
  /// derivatives if the trajectory ends at rest (it always does when produced by this module).
  TrajectoryPoint sample(double t_s) const;

  /// Largest speed / acceleration norm found on a grid of `dt_s`.
  double maxSpeed(double dt_s = 0.01) const;
  double maxAcceleration(double dt_s = 0.01) const;

  /// Evaluates sum_k c_k d^order/dt^order t^k at local time t.
  static Eigen::Vector3d evalPiece(const PieceCoeffs& c, double t_s, int order);

 private:
  std::vector<PieceCoeffs> pieces_;
  std::vector<double> durations_s_;
  double total_s_ = 0.0;
  YawProfile yaw_;
};

/// Brakes from (p, v, a) along -v at `decel_mps2` until rest, then holds. Acceleration jumps to the
/// braking value at t = 0 (the controller absorbs it); the stop distance is |v|^2 / (2 decel).
Trajectory emergencyStop(const Eigen::Vector3d& p_world_m, const Eigen::Vector3d& v_world_mps,
                         double decel_mps2, double yaw_rad);

}  // namespace efs::traj
