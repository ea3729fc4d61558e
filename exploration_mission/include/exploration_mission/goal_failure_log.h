// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// A CSV line per goal the local planner gave up on: where the goal and the vehicle were, the
// local planner's reason, and whether the exploration planner set the viewpoint aside for it.
// What a person reads to see why a flight hovered, or came back later to a place it had been
// (explore_mission writes it beside plan_log.csv).
#pragma once

#include <ostream>
#include <vector>

#include "exploration_mission/exploration_mission.h"

namespace efs::mission {

void writeGoalFailureLog(std::ostream& out, const std::vector<GoalFailureRecord>& records);

}  // namespace efs::mission
