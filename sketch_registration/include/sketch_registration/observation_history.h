// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The walls the robot has seen over the whole flight, in the world frame. The local map that a
// frame carries is a window (lio_bridge keeps 60 m, Scale-ICP reads 40 m of it); in a paper-size
// world that window is a straight stretch of passage or a few bays of a garage, which many places
// of a sketch fit, and whose fit leaves the scale and yaw loose: in the 500 m cave a hypothesis
// within a metre of the truth around the robot had its scale 1-2 % off, 4-5 m of placement error
// over the sketch (2026-11-25). The walls seen earlier, farther than the window, pin the scale
// and yaw and tell a place that fits only the window from the true one.
//
// One point per `cell_m` cell. A remembered wall is forgotten where a frame now sees passage
// (a column with free space between a lower and an upper surface) within forget_radius_m of it:
// a column first taken for a wall, e.g. a car seen from afar without the ceiling above it, turns
// out to be passage later (in the paper-size garage the truth explained 66 % of the remembered
// walls while they were kept). Otherwise the memory stays even within the frame's range: the
// observation's height band follows the robot, and on the cave's slopes (up to 0.35) walls 20-40
// m behind drop out of it although nothing contradicts them.
#pragma once

#include <unordered_map>

#include "sketch_registration/types.h"

namespace efs::registration {

struct ObservationHistoryConfig {
  bool enabled = true;
  double cell_m = 1.0;            ///< one remembered wall point per cell [world m]
  double forget_radius_m = 0.35;  ///< passage seen this close to a remembered wall erases it [m]
  /// Walls farther than this from the robot are forgotten [world m]; bounds memory and the
  /// odometry drift a check can accumulate. 0 keeps everything.
  double radius_m = 400.0;
  /// At most this many remembered points (outside the current observation) join Scale-ICP and
  /// the history check (evenly thinned).
  int max_points = 600;
  /// The history check runs only once at least this many remembered points lie outside the
  /// current observation (before that the window is all there is).
  int min_points = 60;
  void validate() const;
};

class ObservationHistory {
 public:
  explicit ObservationHistory(const ObservationHistoryConfig& config = {});

  /// Merges one frame's observation: its walls `walls_m` and passage columns `passage_m` (world
  /// frame). Passage erases remembered walls near it, the frame's walls replace what their cells
  /// held, points beyond radius_m are dropped; beyond() are the points farther than
  /// `current_range_m` from `robot_m` (outside the frame's observation).
  void update(const Eigen::Vector2d& robot_m, const Points2d& walls_m, const Points2d& passage_m,
              double current_range_m);

  /// Remembered points outside the last frame's observation range, evenly thinned to
  /// max_points (deterministic order).
  const Points2d& beyond() const { return beyond_; }
  /// All remembered points outside the last frame's observation range (not thinned).
  size_t beyondCount() const { return beyond_count_; }
  size_t size() const { return cells_.size(); }
  void reset();
  const ObservationHistoryConfig& config() const { return config_; }

 private:
  ObservationHistoryConfig config_;
  std::unordered_map<long long, Eigen::Vector2d> cells_;
  Points2d beyond_;
  size_t beyond_count_ = 0;
};

}  // namespace efs::registration
