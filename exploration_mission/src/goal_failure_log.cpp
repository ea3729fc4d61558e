// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/goal_failure_log.h"

#include "exploration_mission/csv_field.h"

namespace efs::mission {

void writeGoalFailureLog(std::ostream& out, const std::vector<GoalFailureRecord>& records) {
  out << "time_s,goal_x_m,goal_y_m,goal_z_m,viewpoint_x_m,viewpoint_y_m,viewpoint_z_m,robot_x_m,"
         "robot_y_m,robot_z_m,failed_plans,status,outcome,message\n";
  const auto xyz = [&out](const Eigen::Vector3d& p) {
    out << p.x() << ',' << p.y() << ',' << p.z() << ',';
  };
  for (const GoalFailureRecord& r : records) {
    out << r.time_s << ',';
    xyz(r.goal_world_m);
    xyz(r.viewpoint_world_m);
    xyz(r.robot_world_m);
    out << r.failed_plans << ',' << traj::toString(r.status) << ',' << planner::toString(r.outcome)
        << ',' << csvQuoted(r.message) << '\n';
  }
}

}  // namespace efs::mission
