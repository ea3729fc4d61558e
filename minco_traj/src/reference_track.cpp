// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/reference_track.h"

#include <algorithm>
#include <utility>

namespace efs::traj {

void ReferenceTrack::install(Trajectory traj, double start_s) {
  previous_ = std::move(current_);
  previous_start_s_ = current_start_s_;
  current_ = std::move(traj);
  current_start_s_ = start_s;
  ++revision_;
}

std::optional<ReferenceSample> ReferenceTrack::at(double time_s) const {
  if (!warp_) return unwarpedAt(time_s);
  // Chain rule of p(tau(t)), with the rate of tau falling at the constant 1 / stop_s.
  const double dt = std::clamp(time_s - warp_->t0_s, 0.0, warp_->stop_s);
  const bool slowing = warp_->stop_s > 0.0 && time_s - warp_->t0_s < warp_->stop_s;
  const double rate = warp_->stop_s > 0.0 ? 1.0 - dt / warp_->stop_s : 0.0;
  const double rate_dot = slowing ? -1.0 / warp_->stop_s : 0.0;
  const double tau = warp_->t0_s + dt - (warp_->stop_s > 0.0 ? 0.5 * dt * dt / warp_->stop_s : 0.0);
  std::optional<ReferenceSample> s = unwarpedAt(tau);
  if (!s) return s;
  const Eigen::Vector3d v = s->v_world_mps, a = s->a_world_mps2, j = s->j_world_mps3;
  s->v_world_mps = rate * v;
  s->a_world_mps2 = rate * rate * a + rate_dot * v;
  s->j_world_mps3 = rate * rate * rate * j + 3.0 * rate * rate_dot * a;
  s->yaw_rate_radps *= rate;
  return s;
}

std::optional<ReferenceSample> ReferenceTrack::unwarpedAt(double time_s) const {
  const bool use_previous = previous_ && time_s < current_start_s_;
  const Trajectory* traj = use_previous ? &*previous_ : current();
  if (!traj || traj->empty()) return std::nullopt;
  const double start = use_previous ? previous_start_s_ : current_start_s_;
  const TrajectoryPoint pt = traj->sample(std::max(0.0, time_s - start));
  ReferenceSample s;
  s.p_world_m = pt.p_world_m;
  s.v_world_mps = pt.v_world_mps;
  s.a_world_mps2 = pt.a_world_mps2;
  s.j_world_mps3 = pt.j_world_mps3;
  s.yaw_rad = pt.yaw_rad;
  s.yaw_rate_radps = pt.yaw_rate_radps;
  s.valid = true;
  return s;
}

void ReferenceTrack::holdAlongPath(double time_s, double stop_s) {
  if (warp_) return;
  warp_ = Warp{time_s, std::max(0.0, stop_s)};
  ++revision_;
}

void ReferenceTrack::endHold() {
  if (!warp_) return;
  warp_.reset();
  ++revision_;
}

void ReferenceTrack::dropPrevious() {
  if (!previous_) return;
  previous_.reset();
  ++revision_;
}

}  // namespace efs::traj
