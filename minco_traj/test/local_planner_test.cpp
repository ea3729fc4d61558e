// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <limits>

#include "efs_common/config_check.h"
#include "minco_traj/local_planner.h"

namespace efs::traj {
namespace {

// A 12 x 12 x 3 m room split by a wall at x = 0 with a door around y = 1 (1.4 m wide by default,
// between occupied cell centres).
LocalGrid doorWorld(double door_width_m = 1.4, double inflation_radius_m = 0.3) {
  LocalGridConfig gc;
  gc.size_x_m = 12;
  gc.size_y_m = 12;
  gc.size_z_m = 3;
  gc.inflation_radius_m = inflation_radius_m;
  LocalGrid grid(gc, Eigen::Vector3d(0, 0, 1));
  grid.setAllFree();
  for (double y = -6; y < 6; y += 0.1)
    for (double z = -1; z < 3; z += 0.1)
      if (std::abs(y - 1.0) > 0.5 * door_width_m) grid.setOccupied({0.05, y, z});
  return grid;
}

double minObstacleDistance(const LocalGrid& grid, const Trajectory& tr) {
  std::vector<Eigen::Vector3d> occ;
  grid.occupiedCentersInBox(grid.windowMin(), grid.windowMax(), occ);
  double dmin = 1e9;
  for (double t = 0; t <= tr.duration(); t += 0.02) {
    const Eigen::Vector3d p = tr.position(t);
    for (const auto& o : occ) dmin = std::min(dmin, (o - p).norm());
  }
  return dmin;
}

TEST(LocalPlanner, ThroughTheDoorSafelyAndWithinLimits) {
  const LocalGrid grid = doorWorld();
  LocalPlanner planner;
  PlanRequest req;
  req.p_world_m = {-3, -2, 1};
  req.goal_world_m = {3, -2, 1};
  req.look_at_world_m = {5, -2, 1};
  req.has_look_at = true;
  const PlanResult r = planner.plan(grid, req);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_FALSE(r.emergency_stop);
  const Trajectory& tr = r.trajectory;
  EXPECT_LT((tr.position(tr.duration()) - req.goal_world_m).norm(), 1e-6);
  EXPECT_LE(tr.maxSpeed(0.005), planner.config().optimizer.v_max_mps * 1.02);
  EXPECT_LE(tr.maxAcceleration(0.005), planner.config().optimizer.a_max_mps2);
  // Clearance from every occupied cell centre is kept (up to the corridor tolerance).
  EXPECT_GE(minObstacleDistance(grid, tr), planner.config().corridor.clearance_m - 2e-3);
  EXPECT_LT(LocalPlanner::firstCollisionTime(tr, grid, 0.0, 100.0), 0.0);
  // The sensor ends up looking at the look-at point.
  EXPECT_NEAR(tr.sample(tr.duration() + 5.0).yaw_rad, 0.0, 1e-9);
  double y, rate, acc;
  for (double t = 0; t < tr.duration(); t += 0.01) {
    tr.yaw().sample(t, &y, &rate, &acc);
    EXPECT_LE(std::abs(rate), planner.config().yaw.yaw_rate_max_radps + 1e-9);
  }
}

// A door 0.75 m wide: too narrow for the full clearance (0.45 m from occupied cell centres), wide
// enough for the narrow-passage one (0.36 m). Reached while still moving, along the wall or at
// it, the narrow plan needs its corridor seeded through the braking point: seeded along the
// path alone, 318 of 864 plans through doors 0.7-0.8 m wide (starts at rest or at 0.7-1 m/s)
// failed the final check, leaving their corridor by up to 0.2 m at up to 2.4 m/s; with the
// braking seed 1 of 288 (0.75-0.8 m). In ed21 such failures gave goals up at doors.
TEST(LocalPlanner, ANarrowDoorIsFlownFromAMovingStart) {
  const LocalGrid grid = doorWorld(0.75, LocalGridConfig().inflation_radius_m);
  const LocalPlanner planner;
  const LocalPlannerConfig& c = planner.config();
  int braked_first = 0;
  for (const Eigen::Vector3d& start : {Eigen::Vector3d(-3, 1, 1), Eigen::Vector3d(-1.2, -2, 1)})
    for (const Eigen::Vector3d& v :
         {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0.5, -0.5, 0)}) {
      SCOPED_TRACE("start " + std::to_string(start.y()) + ", velocity " + std::to_string(v.x()) +
                   " " + std::to_string(v.y()));
      PlanRequest req;
      req.p_world_m = start;
      req.v_world_mps = v;
      req.goal_world_m = {3, 1, 1};
      const PlanResult r = planner.plan(grid, req);
      ASSERT_TRUE(r.ok()) << r.message;
      EXPECT_TRUE(r.narrow);
      braked_first += r.braked_first;
      const Trajectory& tr = r.trajectory;
      EXPECT_LT((tr.position(tr.duration()) - req.goal_world_m).norm(), 1e-6);
      EXPECT_LE(tr.maxSpeed(0.005),
                std::max(c.narrow_v_max_mps, v.norm()) * (1 + c.optimizer.velocity_tolerance));
      EXPECT_LE(tr.maxAcceleration(0.005),
                c.optimizer.a_max_mps2 * (1 + c.optimizer.acceleration_tolerance));
      // The corridor keeps narrow_clearance_m from occupied cell centres; the final check lets
      // the result stray narrow_corridor_tolerance_m out of it (2e-3: this check's sampling).
      EXPECT_GE(minObstacleDistance(grid, tr),
                c.narrow_clearance_m - c.narrow_corridor_tolerance_m - 2e-3);
    }
  EXPECT_GT(braked_first, 0);  // contrast: some of them needed the braking seed
}

// From one side of doorWorld's wall to the other, default planner.
PlanResult planThroughTheDoor(const LocalGrid& grid) {
  PlanRequest req;
  req.p_world_m = {-3, -2, 1};
  req.goal_world_m = {3, -2, 1};
  return LocalPlanner().plan(grid, req);
}

TEST(LocalPlanner, PredictsCollisionWithNewObstacles) {
  LocalGrid grid = doorWorld();
  const PlanResult r = planThroughTheDoor(grid);
  ASSERT_TRUE(r.ok()) << r.message;
  const Eigen::Vector3d blocker = r.trajectory.position(0.5 * r.trajectory.duration());
  grid.setOccupied(blocker);
  const double t_hit = LocalPlanner::firstCollisionTime(r.trajectory, grid, 0.0, 100.0);
  EXPECT_GT(t_hit, 0.0);
  EXPECT_LT(t_hit, 0.5 * r.trajectory.duration() + 0.05);
  EXPECT_LT(
      LocalPlanner::firstCollisionTime(r.trajectory, grid, 0.0, 0.2 * r.trajectory.duration()),
      0.0);  // beyond the horizon: no trigger yet
}

TEST(LocalPlanner, PredictsCollisionWithAnObstacleBesideThePath) {
  LocalGrid grid = doorWorld();
  const PlanResult r = planThroughTheDoor(grid);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT(LocalPlanner::firstCollisionTime(r.trajectory, grid, 0.0, 100.0), 0.0);
  // A post 0.2 m beside the path (within the 0.25 m vehicle radius) misses the centre line.
  const double t_mid = 0.25 * r.trajectory.duration();
  const Eigen::Vector3d on_path = r.trajectory.position(t_mid);
  const Eigen::Vector3d side =
      r.trajectory.velocity(t_mid).cross(Eigen::Vector3d::UnitZ()).normalized();
  for (double z = -1.0; z <= 1.0; z += 0.1)
    grid.setOccupied(on_path + 0.2 * side + z * Eigen::Vector3d::UnitZ());
  for (double t = 0.0; t <= r.trajectory.duration(); t += 0.01)
    ASSERT_NE(grid.state(r.trajectory.position(t)), CellState::kOccupied);
  const double t_hit = LocalPlanner::firstCollisionTime(r.trajectory, grid, 0.0, 100.0);
  EXPECT_GT(t_hit, 0.0);
  EXPECT_LT(t_hit, t_mid + 0.05);
  // Contrast: with a clearance below the post's distance nothing is predicted.
  EXPECT_LT(LocalPlanner::firstCollisionTime(r.trajectory, grid, 0.0, 100.0, 0.1), 0.0);
}

// At 4 m/s away from the door, the corridor around the shortest path (behind the vehicle) has no
// room to brake in; seeding it through the braking point first gives a plan that turns back.
TEST(LocalPlanner, FastVehicleHeadingAwayBrakesFirst) {
  const LocalGrid grid = doorWorld();
  PlanRequest req;
  req.p_world_m = {-2, -2, 1};
  req.v_world_mps = {-4, 0, 0};
  req.goal_world_m = {3, -2, 1};
  LocalPlannerConfig without;
  without.braking_first_min_speed_mps = 50.0;
  const PlanResult refused = LocalPlanner(without).plan(grid, req);
  EXPECT_EQ(refused.status, PlanStatus::kOptimizationFailed);
  EXPECT_TRUE(refused.emergency_stop);

  const LocalPlanner planner;
  const PlanResult r = planner.plan(grid, req);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_TRUE(r.braked_first);
  const Trajectory& tr = r.trajectory;
  EXPECT_LT((tr.velocity(0) - req.v_world_mps).norm(), 1e-9);
  EXPECT_LT((tr.position(tr.duration()) - req.goal_world_m).norm(), 1e-6);
  // It went on backwards before turning: the stop lies beyond 4^2 / (2 a_max) from the start.
  double min_x = req.p_world_m.x();
  for (double t = 0; t <= tr.duration(); t += 0.01) min_x = std::min(min_x, tr.position(t).x());
  EXPECT_LT(min_x, req.p_world_m.x() - 16.0 / (2.0 * planner.config().optimizer.a_max_mps2));
  EXPECT_LE(tr.maxSpeed(0.005), planner.config().optimizer.v_max_mps * 1.02);
  EXPECT_LE(tr.maxAcceleration(0.005), planner.config().optimizer.a_max_mps2);
  EXPECT_GE(minObstacleDistance(grid, tr), planner.config().corridor.clearance_m - 2e-3);

  // Slow vehicles take the shortest path as before.
  req.v_world_mps = {-1, 0, 0};
  const PlanResult slow = planner.plan(grid, req);
  ASSERT_TRUE(slow.ok()) << slow.message;
  EXPECT_FALSE(slow.braked_first);
}

TEST(LocalPlanner, MovingStartAndGoalInsideObstacle) {
  const LocalGrid grid = doorWorld();
  PlanRequest req;
  req.p_world_m = {-3, -2, 1};
  req.v_world_mps = {1.5, 0.5, 0};
  req.goal_world_m = {0.05, -3, 1};  // inside the wall: moved to the nearest free cell
  LocalPlannerConfig cfg;
  cfg.astar.goal_search_radius_m = 0.5;
  const PlanResult r = LocalPlanner(cfg).plan(grid, req);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_TRUE(r.goal_adjusted);
  EXPECT_LT((r.trajectory.velocity(0) - req.v_world_mps).norm(), 1e-9);
  // The substitute goal lies just outside this grid's 0.3 m inflation, inside the default
  // check clearance (made for the 0.45 m default): check with the 0.25 m vehicle radius.
  EXPECT_LT(LocalPlanner::firstCollisionTime(r.trajectory, grid, 0.0, 100.0, 0.25), 0.0);
}

TEST(LocalPlanner, StartInCollisionEscapesOrStops) {
  const LocalGrid grid = doorWorld();
  PlanRequest req;
  req.p_world_m = {-0.2, -2, 1};  // 0.25 m from the wall centres: inside the inflation
  req.goal_world_m = {-3, -2, 1};
  PlanResult r = LocalPlanner().plan(grid, req);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_TRUE(r.start_escaped);
  EXPECT_LT(LocalPlanner::firstCollisionTime(r.trajectory, grid, 0.0, 100.0), 0.0);

  LocalPlannerConfig strict;
  strict.astar.start_escape_radius_m = 0.05;
  req.v_world_mps = {-1.0, 0, 0};
  r = LocalPlanner(strict).plan(grid, req);
  EXPECT_EQ(r.status, PlanStatus::kStartInCollision);
  EXPECT_TRUE(r.emergency_stop);
  ASSERT_FALSE(r.trajectory.empty());
  EXPECT_LT(r.trajectory.velocity(r.trajectory.duration()).norm(), 1e-9);  // brakes to rest
}

TEST(LocalPlanner, RefusalsCarryAnEmergencyStop) {
  const LocalGrid grid = doorWorld();
  PlanRequest req;
  req.p_world_m = {-3, -2, 1};
  req.v_world_mps = {2, 0, 0};
  req.goal_world_m = {std::numeric_limits<double>::quiet_NaN(), 0, 0};
  PlanResult r = LocalPlanner().plan(grid, req);
  EXPECT_EQ(r.status, PlanStatus::kBadRequest);
  EXPECT_TRUE(r.emergency_stop);
  EXPECT_NEAR(r.trajectory.durations()[0], 2.0 / 6.0, 1e-12);
  // Goal enclosed (wall without a door): no path.
  LocalGrid closed = doorWorld();
  for (double y = 0; y < 2.1; y += 0.1)
    for (double z = -1; z < 3; z += 0.1) closed.setOccupied({0.05, y, z});
  req.goal_world_m = {3, -2, 1};
  r = LocalPlanner().plan(closed, req);
  EXPECT_EQ(r.status, PlanStatus::kGoalUnreachable);
  EXPECT_TRUE(r.emergency_stop);
}

TEST(LocalPlanner, AlreadyAtGoalGivesAShortHold) {
  const LocalGrid grid = doorWorld();
  PlanRequest req;
  req.p_world_m = {-3, -2, 1};
  req.goal_world_m = req.p_world_m;
  const PlanResult r = LocalPlanner().plan(grid, req);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LT(r.trajectory.maxSpeed(0.01), 0.05);
  EXPECT_LT((r.trajectory.position(r.trajectory.duration()) - req.p_world_m).norm(), 1e-9);
}

TEST(LocalPlanner, ConfigValidationReachesNestedKeys) {
  LocalPlannerConfig cfg;
  cfg.optimizer.a_max_mps2 = 0.0;
  try {
    cfg.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("traj_opt.a_max_mps2"), std::string::npos);
  }
  LocalPlannerConfig loose;
  loose.narrow_corridor_tolerance_m = 0.3;  // more than the margin narrow_clearance_m has
  try {
    loose.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("narrow_corridor_tolerance_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace efs::traj
