// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/stall_watch.h"

#include <algorithm>
#include <cmath>

#include "efs_common/config_check.h"

namespace efs::planner {

void StallConfig::validate() const {
  requireInRange("last_resort_patience_s", patience_s, 0.0, 1.0e6);
  requireInRange("last_resort_min_gain_fraction", min_gain_fraction, 1e-9, 1.0);
}

StallWatch::StallWatch(StallConfig config) : config_(config) { config_.validate(); }

void StallWatch::record(double time_s, size_t well_observed_cells) {
  if (!base_time_s_ || well_observed_cells >= base_cells_ + cellsToGain()) {
    base_time_s_ = time_s;
    base_cells_ = well_observed_cells;
  }
}

bool StallWatch::stalled(double time_s) const {
  return config_.patience_s > 0.0 && base_time_s_ && time_s - *base_time_s_ >= config_.patience_s;
}

std::optional<double> StallWatch::lastGainTime_s() const { return base_time_s_; }

size_t StallWatch::cellsToGain() const {
  return std::max<size_t>(1, static_cast<size_t>(std::ceil(config_.min_gain_fraction *
                                                           static_cast<double>(base_cells_))));
}

}  // namespace efs::planner
