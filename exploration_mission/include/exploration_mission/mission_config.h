// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Configuration of one closed-loop exploration flown in-process: the same core classes the ROS
// nodes wrap (simulator, local map, registration, exploration manager, trajectory server,
// controller), each with its own Config, plus the mission's own limits.
#pragma once

#include "lio_bridge/local_map.h"
#include "marsim_worlds/simulation_session.h"
#include "minco_traj/trajectory_server.h"
#include "prior_guided_planner/exploration_manager.h"
#include "prior_guided_planner/mission_map.h"
#include "se3_controller/se3_controller.h"
#include "sketch_registration/sketch_registration.h"

namespace efs::mission {

struct MissionConfig {
  sim::SimulationSessionConfig session;
  /// Accumulated map the registration frames are cut from (lio_bridge's local map).
  lio::LocalMapConfig registration_map;
  double registration_rate_hz = 0.2;  ///< frames per second of simulated time (paper: 0.2 Hz)
  registration::SketchRegistrationConfig registration;
  planner::ExplorationManagerConfig exploration;
  /// What the mission leaves behind (dense cloud, occupancy, track, registration).
  planner::MissionMapConfig mission_map;
  /// Keep the dense cloud and the track for saveMap(); benchmarks that save nothing turn it off
  /// (on a 2 km cave the cloud is hundreds of MB per trial).
  bool record_map = true;
  traj::TrajectoryServerConfig trajectory;
  control::Se3ControllerConfig controller;
  double control_rate_hz = 100.0;  ///< PositionCommand sampling and controller rate
  double time_limit_s = 2000.0;    ///< simulated seconds (paper protocol)
  double coverage_goal = 0.95;     ///< a run below this coverage counts as failed
  double trajectory_log_period_s = 0.5;
  /// Fault injection: each scan reaches the exploration planner this long after it was taken
  /// [s], while odometry stays current (a loaded onboard computer, or a map node behind the
  /// odometry). 0: at once, as the nodes see it on an idle machine.
  double planner_scan_latency_s = 0.0;
  /// The planner's target is updated at this rate, as the node's timer does (plan_rate_hz);
  /// 0: after every scan.
  double planner_update_rate_hz = 0.0;
  /// Throws efs::ConfigError naming the key (also for any sub-config).
  void validate() const;
};

}  // namespace efs::mission
