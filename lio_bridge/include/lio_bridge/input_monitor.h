// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Health of the LIO input: every odometry sample is checked before the suite uses it. A sample
// with NaNs, a timestamp that goes backwards, or a position jump no vehicle could fly is refused
// with a reason; silence longer than a timeout makes the input stale. Downstream nodes hold
// (hover, freeze the plan) while the input is not healthy.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>

namespace efs::lio {

struct OdometrySample {
  double stamp_s = 0.0;
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
};

struct InputMonitorConfig {
  /// No sample for longer than this makes the input stale [s].
  double stale_timeout_s = 0.2;
  /// Implied speed above this between consecutive samples is a jump (relocalisation, glitch)
  /// [m/s]. Well above the vehicle's 4 m/s limit so noise never triggers it.
  double max_speed_mps = 15.0;
  /// Jumps smaller than this are never flagged, whatever the time step [m].
  double min_jump_m = 0.5;

  void validate() const;
};

enum class InputHealth { kNoData, kHealthy, kStale };

const char* toString(InputHealth health);

class InputMonitor {
 public:
  explicit InputMonitor(const InputMonitorConfig& config = {});

  enum class Verdict { kAccepted, kRejected, kJump };
  struct Result {
    Verdict verdict = Verdict::kAccepted;
    std::string reason;  ///< empty when accepted
  };

  /// Checks a new sample. A rejected sample is ignored (the previous accepted one stays the
  /// reference). A jump is reported once and then taken as the new reference, so a relocalised
  /// LIO is followed rather than refused forever.
  Result check(const OdometrySample& sample);

  /// Health at time `now_s` (injected clock).
  InputHealth health(double now_s) const;

  const std::optional<OdometrySample>& last() const { return last_; }
  int jumpCount() const { return jumps_; }
  int rejectedCount() const { return rejected_; }

 private:
  InputMonitorConfig config_;
  std::optional<OdometrySample> last_;
  int jumps_ = 0;
  int rejected_ = 0;
};

}  // namespace efs::lio
