// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/registration_log.h"

#include "exploration_mission/csv_field.h"

namespace efs::mission {

void writeRegistrationLog(std::ostream& out, const std::vector<HypothesisRecord>& records) {
  out << "time_s,status,hypotheses,best_id,best_fitness_m,best_confidence,best_coverage,"
         "best_scale,best_yaw_rad,best_x_m,best_y_m,best_reflected,best_stretch,"
         "best_stretch_axis_rad,message\n";
  for (const HypothesisRecord& r : records) {
    out << r.time_s << ',' << registration::toString(r.status) << ',' << r.hypotheses.size() << ',';
    if (r.hypotheses.empty()) {
      out << ",,,,,,,,,,";
    } else {
      const registration::Hypothesis& h = r.hypotheses.front();
      const Sim2& T = h.T_world_sketch;
      out << h.id << ',' << h.fitness_m << ',' << h.confidence << ',' << h.coverage << ','
          << T.scale << ',' << T.yaw_rad << ',' << T.t_m.x() << ',' << T.t_m.y() << ','
          << (T.reflected ? 1 : 0) << ',' << T.stretch << ',' << T.stretch_axis_rad;
    }
    out << ',' << csvQuoted(r.message) << '\n';
  }
}

}  // namespace efs::mission
