// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Where the vehicle was at a past instant, from the odometry of the last few seconds.
// A scan is ray cast from the sensor's position at the scan's stamp. A node that takes "the
// latest odometry" instead is right only while it keeps up: a scan handled 0.5 s late behind a
// planning cycle, at 4 m/s, would clear its rays from a point 2 m away and carve free space
// through floors and walls (seen on a loaded 2-core machine: a mission flew into a cave floor).
#pragma once

#include <Eigen/Core>

#include <deque>
#include <optional>
#include <string>

namespace efs {

struct PositionHistoryConfig {
  double keep_s = 3.0;      ///< samples older than the newest by more than this are dropped
  double max_gap_s = 0.25;  ///< no interpolation across a wider gap (odometry lost)
  double max_extrapolation_s = 0.05;  ///< a stamp this far past the newest sample still answers
  /// Throws efs::ConfigError naming the key, prefixed with `key_prefix` (e.g. "scan_origin/").
  void validate(const std::string& key_prefix = "") const;
};

class PositionHistory {
 public:
  explicit PositionHistory(const PositionHistoryConfig& config = {});

  /// Adds one odometry sample. Non-finite input is refused (false). A stamp older than the newest
  /// is inserted in order; one that goes back more than keep_s (a clock reset) clears the history.
  bool add(double stamp_s, const Eigen::Vector3d& p_world_m);

  /// The position at stamp_s, linearly interpolated between the samples around it, or held from
  /// the newest one up to max_extrapolation_s past it. Empty, with `why` set when given, if the
  /// stamp lies before the history, beyond the extrapolation, or inside a gap wider than max_gap_s.
  std::optional<Eigen::Vector3d> at(double stamp_s, std::string* why = nullptr) const;

  /// Mean velocity over the `window_s` up to the newest sample (window_s > 0), from the positions
  /// then and now; empty when the history does not reach back that far or spans a gap.
  std::optional<Eigen::Vector3d> velocity(double window_s) const;

  bool empty() const { return samples_.empty(); }
  size_t size() const { return samples_.size(); }
  void clear() { samples_.clear(); }

 private:
  struct Sample {
    double stamp_s;
    Eigen::Vector3d p_world_m;
  };
  PositionHistoryConfig config_;
  std::deque<Sample> samples_;
};

}  // namespace efs
