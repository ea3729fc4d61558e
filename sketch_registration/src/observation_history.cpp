// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/observation_history.h"

#include <algorithm>
#include <vector>

#include "efs_common/config_check.h"
#include "sketch_registration/observation.h"

namespace efs::registration {

void ObservationHistoryConfig::validate() const {
  requireInRange("history_cell_m", cell_m, 0.05, 100.0);
  requireThat(forget_radius_m >= 0.0 && forget_radius_m < cell_m, "history_forget_radius_m",
              "must be in [0, history_cell_m)");
  requireInRange("history_radius_m", radius_m, 0.0, 1e6);
  requireInRange("history_max_points", max_points, 1, 10000000);
  requireInRange("history_min_points", min_points, 1, 10000000);
}

ObservationHistory::ObservationHistory(const ObservationHistoryConfig& config) : config_(config) {
  config_.validate();
}

void ObservationHistory::reset() {
  cells_.clear();
  beyond_.clear();
  beyond_count_ = 0;
}

void ObservationHistory::update(const Eigen::Vector2d& robot_m, const Points2d& walls_m,
                                const Points2d& passage_m, double current_range_m) {
  if (!config_.enabled || !robot_m.allFinite()) return;
  const double f2 = config_.forget_radius_m * config_.forget_radius_m;
  const Eigen::Vector2d step(config_.cell_m, config_.cell_m);
  for (const auto& p : passage_m) {
    if (!p.allFinite()) continue;
    // A remembered point within forget_radius_m (< cell_m) lies in this cell or a neighbour.
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const auto it = cells_.find(
            gridCellKey(p + Eigen::Vector2d(dx, dy).cwiseProduct(step), config_.cell_m));
        if (it != cells_.end() && (it->second - p).squaredNorm() <= f2) cells_.erase(it);
      }
    }
  }
  for (const auto& p : walls_m) {
    if (p.allFinite()) cells_[gridCellKey(p, config_.cell_m)] = p;
  }
  const double r2 = current_range_m * current_range_m;
  const double forget2 = config_.radius_m * config_.radius_m;
  std::vector<std::pair<long long, Eigen::Vector2d>> beyond;
  for (auto it = cells_.begin(); it != cells_.end();) {
    const double d2 = (it->second - robot_m).squaredNorm();
    if (config_.radius_m > 0.0 && d2 > forget2) {
      it = cells_.erase(it);
    } else {
      if (d2 > r2) beyond.emplace_back(it->first, it->second);
      ++it;
    }
  }
  // Sorted by cell so that the thinned set does not depend on the hash table's order.
  std::sort(beyond.begin(), beyond.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  Points2d all;
  all.reserve(beyond.size());
  for (const auto& [key, p] : beyond) all.push_back(p);
  beyond_count_ = all.size();
  beyond_ = thinEvenly(all, static_cast<size_t>(config_.max_points));
}

}  // namespace efs::registration
