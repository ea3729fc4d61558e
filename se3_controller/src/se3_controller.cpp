// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "se3_controller/se3_controller.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "efs_common/config_check.h"

namespace efs::control {

void Se3ControllerConfig::validate() const {
  requireInRange("se3.mass_kg", mass_kg, 0.01, 100.0);
  requireInRange("se3.gravity_mps2", gravity_mps2, 1.0, 20.0);
  for (int i = 0; i < 3; ++i) {
    requireInRange("se3.kp_position", kp_position[i], 0.0, 1000.0);
    requireInRange("se3.kv_velocity", kv_velocity[i], 0.0, 1000.0);
    requireInRange("se3.kR", kR[i], 0.0, 1e4);
    requireInRange("se3.kOm", kOm[i], 0.0, 1e4);
  }
  requirePositive("se3.max_position_error_m", max_position_error_m);
  requireInRange("se3.max_tilt_rad", max_tilt_rad, 0.05, 1.4);
  requireInRange("se3.min_thrust_accel_mps2", min_thrust_accel_mps2, 0.0, gravity_mps2);
  requireInRange("se3.odom_timeout_s", odom_timeout_s, 1e-3, 10.0);
  requireInRange("se3.command_timeout_s", command_timeout_s, 1e-3, 60.0);
  requireInRange("se3.feedforward_on_odometry_loss_s", feedforward_on_odometry_loss_s, 0.0, 60.0);
  requireInRange("se3.dead_reckoning_lag_s", dead_reckoning_lag_s, 0.0, 2.0);
  requireInRange("se3.imu_max_age_s", imu_max_age_s, 0.0, 1.0);
  requireInRange("se3.brake_accel_mps2", brake_accel_mps2, 0.0, 0.8 * gravity_mps2);
  requireInRange("se3.brake_attitude_lag_s", brake_attitude_lag_s, 0.0, 2.0);
  requireInRange("se3.descent_delay_s", descent_delay_s, 0.0, 60.0);
  requireInRange("se3.descent_accel_mps2", descent_accel_mps2, 0.0, 0.5 * gravity_mps2);
  requireInRange("se3.descent_speed_mps", descent_speed_mps, 0.0, 5.0);
  requireInRange("se3.hover_throttle_min", hover_throttle_min, 0.01, 0.99);
  requireInRange("se3.hover_throttle_max", hover_throttle_max, hover_throttle_min, 0.99);
  requireInRange("se3.hover_throttle_initial", hover_throttle_initial, hover_throttle_min,
                 hover_throttle_max);
  requirePositive("se3.hover_estimator_time_constant_s", hover_estimator_time_constant_s);
}

const char* toString(ControlMode m) {
  switch (m) {
    case ControlMode::kTracking:
      return "tracking";
    case ControlMode::kHoldPosition:
      return "hold_position";
    case ControlMode::kFeedForward:
      return "feed_forward";
    case ControlMode::kLevelDescend:
      return "level_descend";
    case ControlMode::kNoOdometry:
      return "no_odometry";
  }
  return "?";
}

Eigen::Matrix3d attitudeFromThrust(const Eigen::Vector3d& z_in, double yaw) {
  const Eigen::Vector3d z = z_in.normalized();
  const Eigen::Vector3d xc(std::cos(yaw), std::sin(yaw), 0.0);
  Eigen::Vector3d y = z.cross(xc);
  Eigen::Matrix3d R;
  if (y.norm() < 1e-6) {  // thrust along the heading (90 deg pitch): use the lateral axis instead
    const Eigen::Vector3d yc(-std::sin(yaw), std::cos(yaw), 0.0);
    const Eigen::Vector3d x = yc.cross(z).normalized();
    y = z.cross(x);
    R << x, y, z;
    return R;
  }
  y.normalize();
  R << y.cross(z), y, z;
  return R;
}

Eigen::Vector3d bodyRatesFromJerk(const Eigen::Matrix3d& R, const Eigen::Vector3d& f,
                                  const Eigen::Vector3d& fdot, double yaw, double yaw_rate) {
  const double c = f.norm();
  if (c < 1e-9) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d x = R.col(0), y = R.col(1), z = R.col(2);
  // Rate of the thrust direction: z_dot = (fdot - z (z . fdot)) / c = omega_y x - omega_x y.
  const Eigen::Vector3d zdot = (fdot - z * z.dot(fdot)) / c;
  const Eigen::Vector3d xc(std::cos(yaw), std::sin(yaw), 0.0),
      yc(-std::sin(yaw), std::cos(yaw), 0.0);
  const Eigen::Vector3d u = z.cross(xc);
  const double nu = u.norm();
  double wz = 0.0;
  if (nu > 1e-6) {
    // y = u / |u| and omega_z = -ydot . x; only the part of udot orthogonal to u survives.
    const Eigen::Vector3d udot = zdot.cross(xc) + yaw_rate * z.cross(yc);
    wz = -udot.dot(x) / nu;
  }
  return Eigen::Vector3d(-zdot.dot(y), zdot.dot(x), wz);
}

FlatAttitude flatAttitude(const Eigen::Vector3d& a, const Eigen::Vector3d& j, double yaw,
                          double yaw_rate, double g) {
  FlatAttitude out;
  const Eigen::Vector3d f = a + Eigen::Vector3d(0, 0, g);
  out.thrust_accel_mps2 = f.norm();
  out.R_world_body = attitudeFromThrust(f, yaw);
  out.omega_body_radps = bodyRatesFromJerk(out.R_world_body, f, j, yaw, yaw_rate);
  return out;
}

namespace {
inline Eigen::Vector3d vee(const Eigen::Matrix3d& m) { return {m(2, 1), m(0, 2), m(1, 0)}; }
inline double yawOf(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

bool finite(const OdometryState& o) {
  return std::isfinite(o.stamp_s) && o.p_world_m.allFinite() && o.v_world_mps.allFinite() &&
         o.q_world_body.coeffs().allFinite() && o.omega_body_radps.allFinite() &&
         o.q_world_body.norm() > 0.5;
}
bool finite(const FlatReference& r) {
  return std::isfinite(r.stamp_s) && r.p_world_m.allFinite() && r.v_world_mps.allFinite() &&
         r.a_world_mps2.allFinite() && r.j_world_mps3.allFinite() && std::isfinite(r.yaw_rad) &&
         std::isfinite(r.yaw_rate_radps);
}
}  // namespace

Se3Controller::Se3Controller(const Se3ControllerConfig& cfg) : cfg_(cfg) {
  cfg_.validate();
  hover_throttle_ = cfg_.hover_throttle_initial;
}

void Se3Controller::reset() {
  have_odom_ = holding_ = descending_ = have_acc_stamp_ = reckoning_ = have_imu_ = false;
  imu_stamp_s_ = 0.0;
  imu_samples_.clear();
  hover_throttle_ = cfg_.hover_throttle_initial;
  last_thrust_cmd_ = 0.0;
}

void Se3Controller::observeAcceleration(const Eigen::Vector3d& a_world, const Eigen::Quaterniond& q,
                                        double dt_s) {
  if (!(dt_s > 0.0) || !a_world.allFinite() || !q.coeffs().allFinite() || last_thrust_cmd_ <= 0.0)
    return;
  const double g = cfg_.gravity_mps2;
  const double r33 = q.normalized().toRotationMatrix()(2, 2);
  const double vertical = a_world.z() + g;      // = (u / hover) g r33 for normalised thrust u
  if (r33 < 0.7 || vertical < 0.3 * g) return;  // far from the regime the model describes
  const double measured = last_thrust_cmd_ * g * r33 / vertical;
  const double alpha = dt_s / (cfg_.hover_estimator_time_constant_s + dt_s);
  hover_throttle_ = std::clamp(hover_throttle_ + alpha * (measured - hover_throttle_),
                               cfg_.hover_throttle_min, cfg_.hover_throttle_max);
}

void Se3Controller::fillOutputs(const OdometryState& odom, const Eigen::Vector3d& f_acc, double yaw,
                                const Eigen::Vector3d& omega_d, ControlOutput& out) {
  const Eigen::Matrix3d Rd = attitudeFromThrust(f_acc, yaw);
  const Eigen::Matrix3d R = odom.q_world_body.normalized().toRotationMatrix();
  const Eigen::Vector3d F = cfg_.mass_kg * f_acc;
  out.attitude_error = 0.5 * vee(Rd.transpose() * R - R.transpose() * Rd);
  out.rate_error_radps = odom.omega_body_radps - R.transpose() * Rd * omega_d;
  out.collective_thrust_N = F.dot(R.col(2));
  auto& s = out.so3;
  s.force_world_N = F;
  s.orientation = Eigen::Quaterniond(Rd);
  s.angular_velocity_body_radps = omega_d;
  s.kR = cfg_.kR;
  s.kOm = cfg_.kOm;
  s.current_yaw_rad = yawOf(R);
  s.enable_motors = true;
  auto& a = out.attitude;
  a.type_mask = 0;
  a.orientation = s.orientation;
  a.body_rate_radps = omega_d;
  a.thrust = std::clamp(
      std::max(0.0, out.collective_thrust_N) / (cfg_.mass_kg * cfg_.gravity_mps2) * hover_throttle_,
      0.0, 1.0);
  last_thrust_cmd_ = a.thrust;
}

ControlOutput Se3Controller::track(const OdometryState& odom, const FlatReference& ref,
                                   bool feedforward) {
  ControlOutput out;
  out.mode = ControlMode::kTracking;
  Eigen::Vector3d ep = odom.p_world_m - ref.p_world_m;
  if (ep.norm() > cfg_.max_position_error_m) ep *= cfg_.max_position_error_m / ep.norm();
  const Eigen::Vector3d ev = odom.v_world_mps - ref.v_world_mps;
  out.position_error_m = odom.p_world_m - ref.p_world_m;
  out.velocity_error_mps = ev;
  const double g = cfg_.gravity_mps2;
  Eigen::Vector3d f = -cfg_.kp_position.cwiseProduct(ep) - cfg_.kv_velocity.cwiseProduct(ev) +
                      Eigen::Vector3d(0, 0, g);
  if (feedforward) f += ref.a_world_mps2;
  // Keep a minimum collective thrust and a maximum tilt (horizontal part scaled down).
  f.z() = std::max(f.z(), cfg_.min_thrust_accel_mps2);
  const double h = f.head<2>().norm(), hmax = std::tan(cfg_.max_tilt_rad) * f.z();
  if (h > hmax) f.head<2>() *= hmax / h;
  Eigen::Vector3d omega_d = Eigen::Vector3d::Zero();
  if (feedforward) {
    const Eigen::Matrix3d Rd = attitudeFromThrust(f, ref.yaw_rad);
    omega_d = bodyRatesFromJerk(Rd, f, ref.j_world_mps3, ref.yaw_rad, ref.yaw_rate_radps);
  }
  fillOutputs(odom, f, ref.yaw_rad, omega_d, out);
  return out;
}

ControlOutput Se3Controller::levelDescend(double now_s) {
  if (!descending_) {
    descending_ = true;
    descent_start_s_ = now_s;
    brake_velocity_mps_ = last_odom_.v_world_mps.head<2>();
  }
  const double elapsed = now_s - descent_start_s_;
  const double ramp_s =
      cfg_.descent_accel_mps2 > 0.0 ? cfg_.descent_speed_mps / cfg_.descent_accel_mps2 : 0.0;
  const double descending_s = elapsed - cfg_.descent_delay_s;
  const double down = descending_s >= 0.0 && descending_s < ramp_s ? cfg_.descent_accel_mps2 : 0.0;
  // The velocity at the onset, decelerated at brake_accel along its own direction, reaches zero
  // after |v| / a (plus the attitude lag): until then the thrust leans against it. Without odometry
  // this is the best estimate there is, and it stops the vehicle in v^2 / 2a instead of letting it
  // drift.
  Eigen::Vector3d f(0, 0, cfg_.gravity_mps2 - down);
  const double speed = brake_velocity_mps_.norm();
  if (cfg_.brake_accel_mps2 > 0.0 && speed > 1e-3 &&
      elapsed < speed / cfg_.brake_accel_mps2 + cfg_.brake_attitude_lag_s) {
    f.head<2>() = -cfg_.brake_accel_mps2 * brake_velocity_mps_ / speed;
  }
  ControlOutput out;
  out.mode = ControlMode::kLevelDescend;
  const double yaw = yawOf(last_odom_.q_world_body.normalized().toRotationMatrix());
  fillOutputs(last_odom_, f, yaw, Eigen::Vector3d::Zero(), out);
  return out;
}

void Se3Controller::observeImu(const Eigen::Vector3d& a_world_mps2, double stamp_s) {
  if (!a_world_mps2.allFinite() || !std::isfinite(stamp_s)) return;
  have_imu_ = true;
  if (stamp_s >= imu_stamp_s_) {
    imu_stamp_s_ = stamp_s;
    imu_accel_world_ = a_world_mps2;
  }
  if (have_odom_ && stamp_s <= last_odom_.stamp_s) return;  // before the state it would advance
  auto it = imu_samples_.end();
  while (it != imu_samples_.begin() && std::prev(it)->stamp_s > stamp_s) --it;
  imu_samples_.insert(it, {stamp_s, a_world_mps2});
  if (imu_samples_.size() > kMaxImuSamples) imu_samples_.pop_front();
}

ControlOutput Se3Controller::update(const OdometryState& odom,
                                    const std::optional<FlatReference>& reference, double now_s) {
  if (!std::isfinite(now_s)) throw std::invalid_argument("Se3Controller::update: now_s not finite");
  std::ostringstream why;
  const bool odom_ok = finite(odom);
  if (odom_ok) {
    if (odom.has_acceleration && odom.a_world_mps2.allFinite()) {
      if (have_acc_stamp_)
        observeAcceleration(odom.a_world_mps2, odom.q_world_body, odom.stamp_s - last_acc_stamp_s_);
      last_acc_stamp_s_ = odom.stamp_s;
      have_acc_stamp_ = true;
    }
    last_odom_ = odom;
    last_odom_.q_world_body.normalize();
    have_odom_ = true;
    while (!imu_samples_.empty() && imu_samples_.front().stamp_s <= last_odom_.stamp_s)
      imu_samples_.pop_front();
  } else {
    why << "odometry rejected (non-finite value); ";
  }
  ControlOutput out;
  if (!have_odom_) {
    out.mode = ControlMode::kNoOdometry;
    out.so3.enable_motors = false;
    out.so3.kR = cfg_.kR;
    out.so3.kOm = cfg_.kOm;
    why << "no valid odometry yet";
    out.reason = why.str();
    out.odometry_rejected = !odom_ok;
    last_thrust_cmd_ = 0.0;
    return out;
  }
  const double odom_age = now_s - last_odom_.stamp_s;
  const FlatReference ref = reference.value_or(FlatReference{});
  const bool ref_fresh = reference && finite(ref) && now_s - ref.stamp_s <= cfg_.command_timeout_s;
  if (odom_age > cfg_.odom_timeout_s && ref_fresh && !descending_ &&
      odom_age <= cfg_.odom_timeout_s + cfg_.feedforward_on_odometry_loss_s) {
    // Dead reckoning from the last odometry: the commanded acceleration, reached with the
    // attitude loop's lag, integrated; fed back like odometry so the reference is followed.
    if (!reckoning_) {
      reckoning_ = true;
      reckoning_stamp_s_ = last_odom_.stamp_s;
      reckoned_p_ = last_odom_.p_world_m;
      reckoned_v_ = last_odom_.v_world_mps;
      reckoned_a_ = last_accel_cmd_;
    }
    const double dt = std::max(0.0, now_s - reckoning_stamp_s_);
    const double blend =
        cfg_.dead_reckoning_lag_s > 0.0 ? 1.0 - std::exp(-dt / cfg_.dead_reckoning_lag_s) : 1.0;
    const bool imu_fresh =
        have_imu_ && std::isfinite(imu_stamp_s_) && now_s - imu_stamp_s_ <= cfg_.imu_max_age_s;
    auto advance = [this](double dt_s, const Eigen::Vector3d& a) {
      reckoned_p_ += dt_s * reckoned_v_ + 0.5 * dt_s * dt_s * a;
      reckoned_v_ += dt_s * a;
    };
    if (imu_fresh && !imu_samples_.empty()) {
      // From the last odometry again each step, so late samples are not lost.
      reckoned_p_ = last_odom_.p_world_m;
      reckoned_v_ = last_odom_.v_world_mps;
      double t = last_odom_.stamp_s;
      for (const ImuSample& sample : imu_samples_) {
        if (sample.stamp_s > now_s) break;
        advance(sample.stamp_s - t, sample.a_world_mps2);
        t = sample.stamp_s;
      }
      reckoned_a_ = imu_accel_world_;
      advance(std::max(0.0, now_s - t), reckoned_a_);
    } else {
      if (imu_fresh) {
        reckoned_a_ = imu_accel_world_;
      } else {
        reckoned_a_ += blend * (last_accel_cmd_ - reckoned_a_);
      }
      advance(dt, reckoned_a_);
    }
    reckoning_stamp_s_ = now_s;
    OdometryState reckoned = last_odom_;
    reckoned.p_world_m = reckoned_p_;
    reckoned.v_world_mps = reckoned_v_;
    out = track(reckoned, ref, true);
    out.mode = ControlMode::kFeedForward;
    why << "odometry stale (" << odom_age << " s > " << cfg_.odom_timeout_s
        << " s): following the reference on dead reckoning";
  } else if (odom_age > cfg_.odom_timeout_s) {
    out = levelDescend(now_s);
    why << "odometry stale (" << odom_age << " s > " << cfg_.odom_timeout_s << " s)";
  } else {
    descending_ = false;
    reckoning_ = false;
    const bool ref_ok = finite(ref);
    const double ref_age = now_s - ref.stamp_s;
    if (!reference || !ref_ok || ref_age > cfg_.command_timeout_s) {
      if (!holding_) {
        holding_ = true;
        hold_position_ = last_odom_.p_world_m;
        hold_yaw_ = yawOf(last_odom_.q_world_body.toRotationMatrix());
      }
      FlatReference hold;
      hold.p_world_m = hold_position_;
      hold.yaw_rad = hold_yaw_;
      out = track(last_odom_, hold, false);
      out.mode = ControlMode::kHoldPosition;
      if (!reference)
        why << "no reference yet";
      else if (!ref_ok)
        why << "reference rejected (non-finite value)";
      else
        why << "reference stale (" << ref_age << " s > " << cfg_.command_timeout_s << " s)";
    } else {
      holding_ = false;
      out = track(last_odom_, ref, cfg_.use_feedforward);
    }
  }
  out.odometry_rejected = !odom_ok;
  out.reason = why.str();
  last_accel_cmd_ = out.so3.force_world_N / cfg_.mass_kg - Eigen::Vector3d(0, 0, cfg_.gravity_mps2);
  return out;
}

}  // namespace efs::control
