// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The keys of a PositionHistoryConfig under one namespace of a node's parameters, read and
// validated the same way by every node that ray casts scans from their stamped origins.
#pragma once

#include <string>

#include "efs_common/position_history.h"
#include "efs_common_ros/param_reader.h"

namespace efs::ros_common {

/// Reads `ns`/keep_s, `ns`/max_gap_s and `ns`/max_extrapolation_s; throws ConfigError naming the
/// key when one is out of range.
inline PositionHistoryConfig readPositionHistoryConfig(ParamReader& p, const std::string& ns) {
  PositionHistoryConfig c;
  p.get(ns + "/keep_s", c.keep_s);
  p.get(ns + "/max_gap_s", c.max_gap_s);
  p.get(ns + "/max_extrapolation_s", c.max_extrapolation_s);
  c.validate(ns + "/");
  return c;
}

}  // namespace efs::ros_common
