// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Whether an exploration still gains anything: the well-observed surface cells of the
// observation map (ObservationMap::numWellObserved), read at each plan, and when they last grew
// by `min_gain_fraction` of what they were. The exploration manager asks it once a plan finds
// nothing but its last resorts (reached openings that moved on, pockets the sketch vouches for):
// those are looked at while they pay, and given up once `patience_s` passed without that gain. A
// share, not a count: flying through ground already seen still adds cells, seen nearer than before
// (20-25 cells/s in the mine's last-resort stage, where exploring added 300-500), and how many
// cells a look adds grows with the world. Seen in the Pittsburgh mine (README): from 1624 s on
// every plan of a guided flight was a last resort, and in the 376 s to the time limit the vehicle
// visited 69 places across the mine for 0.1 point of coverage, while prior_free had finished.
#pragma once

#include <cstddef>
#include <optional>

namespace efs::planner {

/// Keys as in the planner YAML (`last_resort_patience_s`, `last_resort_min_gain_fraction`).
struct StallConfig {
  /// The last resorts are given up after this long without a gain of min_gain_fraction [s].
  /// 0: never (off).
  double patience_s = 30.0;
  /// The gain that counts as progress: this share of the well-observed cells counted when the
  /// clock last started (at least one cell).
  double min_gain_fraction = 0.002;
  /// Throws efs::ConfigError naming the key.
  void validate() const;
};

class StallWatch {
 public:
  /// Throws efs::ConfigError naming the key of a bad value.
  explicit StallWatch(StallConfig config = {});

  /// The count at `time_s`. Times must not go backwards (the manager refuses such updates
  /// before they get here). The observation map's count never shrinks; a count below the
  /// baseline gains nothing until it climbs the gain above the baseline.
  void record(double time_s, size_t well_observed_cells);
  /// Enabled, and patience_s has passed at `time_s` since the last gain (or since the first
  /// record).
  bool stalled(double time_s) const;
  /// Since when the count has not grown by the gain [s]; unset before the first record.
  std::optional<double> lastGainTime_s() const;
  /// Cells gained since then, at a count of `well_observed_cells`.
  size_t cellsSinceLastGain(size_t well_observed_cells) const {
    return well_observed_cells > base_cells_ ? well_observed_cells - base_cells_ : 0;
  }
  /// The cells the count must gain from the baseline to start the clock again.
  size_t cellsToGain() const;

 private:
  StallConfig config_;
  std::optional<double> base_time_s_;
  size_t base_cells_ = 0;
};

}  // namespace efs::planner
