// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// What the reference is made of at any time: the newest trajectory, the one before it (sampled
// until the newest starts, so a replan that starts plan_from_future_s ahead is seamless), and
// the time warp of a hold along the path (odometry lost). A small value type: TrajectoryServer
// owns one and changes it; a command stream on another thread samples a copy, so a long scan
// insertion or replan never stalls the PositionCommands (seen: 0.2 s gaps at 100 Hz).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>

#include "minco_traj/trajectory.h"

namespace efs::traj {

/// Content of a PositionCommand.
struct ReferenceSample {
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_world_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_world_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d j_world_mps3 = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;
  double yaw_rate_radps = 0.0;
  bool valid = false;  ///< false until the first trajectory / hold point exists
};

class ReferenceTrack {
 public:
  /// `traj` becomes the newest trajectory from start_s on; the newest so far is kept as the
  /// previous one (sampled before start_s).
  void install(Trajectory traj, double start_s);
  /// Reference at time_s (warped while holding); std::nullopt before the first trajectory.
  std::optional<ReferenceSample> at(double time_s) const;
  /// The reference without the hold's warp.
  std::optional<ReferenceSample> unwarpedAt(double time_s) const;

  /// From time_s on the reference slows down along the newest trajectory, its rate falling
  /// linearly from 1 to 0 over stop_s, and stops on it. No-op when already holding.
  void holdAlongPath(double time_s, double stop_s);
  /// Ends the hold (the newest trajectory is sampled unwarped again).
  void endHold();
  /// Nothing before the newest trajectory's start is sampled from another trajectory any more.
  void dropPrevious();
  bool holding() const { return warp_.has_value(); }

  const Trajectory* current() const { return current_ ? &*current_ : nullptr; }
  double currentStart_s() const { return current_start_s_; }
  /// Incremented by every change (install, hold, end of hold): copies are refreshed on change.
  uint64_t revision() const { return revision_; }

 private:
  /// reference(t) = trajectory(tau(t)), tau(t0) = t0, dtau/dt = max(0, 1 - (t - t0) / stop_s).
  struct Warp {
    double t0_s = 0.0;
    double stop_s = 0.0;
  };
  std::optional<Warp> warp_;
  std::optional<Trajectory> current_, previous_;
  double current_start_s_ = 0.0, previous_start_s_ = 0.0;
  uint64_t revision_ = 0;
};

}  // namespace efs::traj
