// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/trajectory.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace efs::traj {

void YawProfile::addSegment(const YawSegment& s) {
  if (!(s.duration_s >= 0.0) || !std::isfinite(s.duration_s))
    throw std::invalid_argument("YawProfile::addSegment: duration must be finite and >= 0");
  segments_.push_back(s);
}

double YawProfile::duration() const {
  double d = 0.0;
  for (const auto& s : segments_) d += s.duration_s;
  return d;
}

void YawProfile::sample(double t_s, double* yaw_rad, double* rate_radps, double* acc_radps2) const {
  double y = hold_yaw_rad_, r = 0.0, a = 0.0;
  t_s = std::max(0.0, t_s);
  if (!segments_.empty()) {
    bool done = false;
    for (const auto& s : segments_) {
      if (t_s <= s.duration_s) {
        y = s.yaw0_rad + s.rate0_radps * t_s + 0.5 * s.acc_radps2 * t_s * t_s;
        r = s.rate0_radps + s.acc_radps2 * t_s;
        a = s.acc_radps2;
        done = true;
        break;
      }
      t_s -= s.duration_s;
    }
    if (!done) {
      const auto& s = segments_.back();
      const double T = s.duration_s;
      y = s.yaw0_rad + s.rate0_radps * T + 0.5 * s.acc_radps2 * T * T;
      r = s.rate0_radps + s.acc_radps2 * T;
      // Held after the end: a profile ending at rest keeps its yaw; otherwise yaw keeps rotating
      // at the final rate (never happens for profiles from YawPlanner, which end at rest).
      y += r * t_s;
      a = 0.0;
    }
  }
  if (yaw_rad) *yaw_rad = y;
  if (rate_radps) *rate_radps = r;
  if (acc_radps2) *acc_radps2 = a;
}

Trajectory::Trajectory(std::vector<PieceCoeffs> pieces, std::vector<double> durations_s)
    : pieces_(std::move(pieces)), durations_s_(std::move(durations_s)) {
  if (pieces_.size() != durations_s_.size())
    throw std::invalid_argument("Trajectory: pieces and durations differ in count");
  for (double d : durations_s_) {
    if (!(d > 0.0) || !std::isfinite(d))
      throw std::invalid_argument("Trajectory: piece durations must be finite and > 0");
    total_s_ += d;
  }
}

int Trajectory::locate(double t_s, double* local_t_s) const {
  if (pieces_.empty()) throw std::logic_error("Trajectory::locate on an empty trajectory");
  t_s = std::clamp(t_s, 0.0, total_s_);
  const int n = pieceCount();
  for (int i = 0; i < n; ++i) {
    if (t_s <= durations_s_[i] || i == n - 1) {
      *local_t_s = std::min(t_s, durations_s_[i]);
      return i;
    }
    t_s -= durations_s_[i];
  }
  *local_t_s = durations_s_.back();
  return n - 1;
}

Eigen::Vector3d Trajectory::evalPiece(const PieceCoeffs& c, double t, int order) {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  // Horner on the differentiated polynomial.
  for (int k = 5; k >= order; --k) {
    double f = 1.0;
    for (int m = 0; m < order; ++m) f *= (k - m);
    r = r * t + f * c.col(k);
  }
  return r;
}

Eigen::Vector3d Trajectory::derivative(double t_s, int order) const {
  double lt = 0.0;
  const bool after_end = t_s > total_s_;
  const int i = locate(t_s, &lt);
  if (after_end && order > 0) return Eigen::Vector3d::Zero();
  return evalPiece(pieces_[i], lt, order);
}

TrajectoryPoint Trajectory::sample(double t_s) const {
  TrajectoryPoint pt;
  pt.t_s = t_s;
  if (!pieces_.empty()) {
    pt.p_world_m = derivative(t_s, 0);
    pt.v_world_mps = derivative(t_s, 1);
    pt.a_world_mps2 = derivative(t_s, 2);
    pt.j_world_mps3 = derivative(t_s, 3);
  }
  yaw_.sample(t_s, &pt.yaw_rad, &pt.yaw_rate_radps, &pt.yaw_acc_radps2);
  return pt;
}

double Trajectory::maxSpeed(double dt_s) const {
  double m = 0.0;
  for (double t = 0.0; t <= total_s_ + 1e-12; t += dt_s) m = std::max(m, velocity(t).norm());
  return std::max(m, velocity(total_s_).norm());
}

double Trajectory::maxAcceleration(double dt_s) const {
  double m = 0.0;
  for (double t = 0.0; t <= total_s_ + 1e-12; t += dt_s) m = std::max(m, acceleration(t).norm());
  return std::max(m, acceleration(total_s_).norm());
}

Trajectory emergencyStop(const Eigen::Vector3d& p, const Eigen::Vector3d& v, double decel_mps2,
                         double yaw_rad) {
  if (!(decel_mps2 > 0.0)) throw std::invalid_argument("emergencyStop: decel_mps2 must be > 0");
  const double speed = v.norm();
  std::vector<PieceCoeffs> pieces;
  std::vector<double> durations;
  if (speed > 1e-6) {
    const Eigen::Vector3d dir = v / speed;
    PieceCoeffs c = PieceCoeffs::Zero();
    c.col(0) = p;
    c.col(1) = v;
    c.col(2) = -0.5 * decel_mps2 * dir;
    const double t_stop = speed / decel_mps2;
    pieces.push_back(c);
    durations.push_back(t_stop);
  }
  PieceCoeffs hold = PieceCoeffs::Zero();
  hold.col(0) = pieces.empty() ? p : Trajectory::evalPiece(pieces[0], durations[0], 0);
  pieces.push_back(hold);
  durations.push_back(1.0);
  Trajectory traj(std::move(pieces), std::move(durations));
  traj.setYaw(YawProfile(yaw_rad));
  return traj;
}

}  // namespace efs::traj
