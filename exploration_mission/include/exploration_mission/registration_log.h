// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// A CSV line per registration frame of a mission: the status, the registration's own words on
// why (the message it publishes), and the best hypothesis. What a person reads to see when and
// why a flight was, or was not, guided by its sketch (explore_mission writes it beside
// plan_log.csv).
#pragma once

#include <ostream>
#include <vector>

#include "exploration_mission/exploration_mission.h"

namespace efs::mission {

void writeRegistrationLog(std::ostream& out, const std::vector<HypothesisRecord>& records);

}  // namespace efs::mission
