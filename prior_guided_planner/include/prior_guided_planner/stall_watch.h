// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Whether an exploration still gains anything: the well-observed surface cells of the
// observation map (ObservationMap::numWellObserved), read at each plan, and when they last grew
// by `min_new_cells`. The exploration manager asks it once a plan finds nothing but its last
// resorts (reached openings that moved on, pockets the sketch vouches for): those are looked at
// while they pay, and given up once `patience_s` passed without that gain. Seen in the
// Pittsburgh mine (README): from 1624 s on every plan of a guided flight was a last resort, and
// in the 376 s to the time limit the vehicle visited 69 places across the mine for 0.1 point of
// coverage, while prior_free had finished.
#pragma once

#include <cstddef>
#include <optional>

namespace efs::planner {

/// Keys as in the planner YAML (`last_resort_patience_s`, `last_resort_min_new_cells`).
struct StallConfig {
  /// The last resorts are given up after this long without min_new_cells more well-observed
  /// surface cells [s]. 0: never (off).
  double patience_s = 0.0;
  /// The gain that counts as progress [cells of the observation map].
  int min_new_cells = 100;
  /// Throws efs::ConfigError naming the key.
  void validate() const;
};

class StallWatch {
 public:
  /// Throws efs::ConfigError naming the key of a bad value.
  explicit StallWatch(StallConfig config = {});

  /// The count at `time_s`. Times must not go backwards (the manager refuses such updates
  /// before they get here). The observation map's count never shrinks; a count below the
  /// baseline gains nothing until it climbs min_new_cells above the baseline.
  void record(double time_s, size_t well_observed_cells);
  /// Enabled, and patience_s has passed at `time_s` since the last gain of min_new_cells (or
  /// since the first record).
  bool stalled(double time_s) const;
  /// Since when the count has not grown by min_new_cells [s]; unset before the first record.
  std::optional<double> lastGainTime_s() const;
  /// Cells gained since then.
  size_t cellsSinceLastGain() const {
    return last_cells_ > base_cells_ ? last_cells_ - base_cells_ : 0;
  }
  const StallConfig& config() const { return config_; }

 private:
  StallConfig config_;
  std::optional<double> base_time_s_;
  size_t base_cells_ = 0;
  size_t last_cells_ = 0;
};

}  // namespace efs::planner
