// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <limits>

#include "efs_common/config_check.h"
#include "efs_common/testing/config_error.h"
#include "minco_traj/trajectory_server.h"

namespace efs::traj {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TrajectoryServerConfig smallConfig() {
  TrajectoryServerConfig c;
  c.grid.size_x_m = 14;
  c.grid.size_y_m = 14;
  c.grid.size_z_m = 3;
  return c;
}

VehicleState at(const Eigen::Vector3d& p) {
  VehicleState s;
  s.p_world_m = p;
  return s;
}

VehicleState fromReference(const ReferenceSample& r) {
  VehicleState s;
  s.p_world_m = r.p_world_m;
  s.v_world_mps = r.v_world_mps;
  s.a_world_mps2 = r.a_world_mps2;
  s.yaw_rad = r.yaw_rad;
  return s;
}

/// A wall of scan points at x = wall_x spanning |y| <= half_width_m, z in [0, 2].
std::vector<Eigen::Vector3f> wallScan(double wall_x, double half_width_m) {
  std::vector<Eigen::Vector3f> pts;
  for (double y = -half_width_m; y <= half_width_m + 1e-9; y += 0.05)
    for (double z = 0.0; z <= 2.0 + 1e-9; z += 0.05)
      pts.emplace_back(static_cast<float>(wall_x), static_cast<float>(y), static_cast<float>(z));
  return pts;
}

bool insideUnion(const std::vector<Polytope>& corridor, const Eigen::Vector3d& p, double tol_m) {
  for (const auto& poly : corridor)
    if (poly.contains(p, tol_m)) return true;
  return false;
}

TEST(TrajectoryServer, NoReferenceBeforeTheFirstPlan) {
  TrajectoryServer server(smallConfig());
  EXPECT_FALSE(server.sample(0.0).valid);
  EXPECT_EQ(server.current(), nullptr);
  EXPECT_EQ(server.update(0.0, at({0, 0, 1})), ServerEvent::kNone);  // no goal: nothing to do
  EXPECT_FALSE(server.sample(0.0).valid);
}

TEST(TrajectoryServer, ReferenceIsContinuousAcrossReplans) {
  TrajectoryServer server(smallConfig());
  server.setGoal({5, 1, 1}, std::nullopt, 0.0);
  ASSERT_EQ(server.update(0.0, at({0, 0, 1})), ServerEvent::kReplanned) << server.lastMessage();
  ASSERT_TRUE(server.sample(0.0).valid);
  EXPECT_LT((server.sample(0.0).p_world_m - Eigen::Vector3d(0, 0, 1)).norm(), 1e-9);
  // Nothing due before the period.
  EXPECT_EQ(server.update(0.5, fromReference(server.sample(0.5))), ServerEvent::kNone);
  // The period elapses: replan from the reference 50 ms ahead, the old one is sampled until then.
  const double t = 1.0;
  ASSERT_EQ(server.update(t, fromReference(server.sample(t))), ServerEvent::kReplanned);
  const double t_switch = server.currentStart_s();
  EXPECT_NEAR(t_switch, t + server.config().plan_from_future_s, 1e-12);
  const ReferenceSample before = server.sample(t_switch - 1e-7);
  const ReferenceSample after = server.sample(t_switch);
  EXPECT_GT(before.v_world_mps.norm(), 0.5);  // mid-flight, not a trivial case
  EXPECT_LT((before.p_world_m - after.p_world_m).norm(), 1e-5);
  EXPECT_LT((before.v_world_mps - after.v_world_mps).norm(), 1e-5);
  EXPECT_LT((before.a_world_mps2 - after.a_world_mps2).norm(), 1e-4);
  EXPECT_NEAR(before.yaw_rad, after.yaw_rad, 1e-5);
  // A new goal mid-flight is continuous too.
  server.setGoal({5, -2, 1}, Eigen::Vector3d(8, -2, 1), 1.3);
  ASSERT_EQ(server.update(1.3, fromReference(server.sample(1.3))), ServerEvent::kReplanned);
  const ReferenceSample b2 = server.sample(server.currentStart_s() - 1e-7);
  const ReferenceSample a2 = server.sample(server.currentStart_s());
  EXPECT_LT((b2.p_world_m - a2.p_world_m).norm(), 1e-5);
  EXPECT_LT((b2.v_world_mps - a2.v_world_mps).norm(), 1e-5);
  EXPECT_LT((b2.a_world_mps2 - a2.a_world_mps2).norm(), 1e-4);
}

TEST(TrajectoryServer, ReplansAroundAnObstacleSeenInANewScan) {
  TrajectoryServer server(smallConfig());
  const Eigen::Vector3d start(0, 0, 1), goal(6, 0, 1);
  server.insertScan(start, {});  // centres the window; the space ahead is still unknown
  server.setGoal(goal, std::nullopt, 0.0);
  ASSERT_EQ(server.update(0.0, at(start)), ServerEvent::kReplanned);
  // The first plan goes straight through the (unknown) wall position.
  EXPECT_NEAR(server.current()->position(0.5 * server.current()->duration()).y(), 0.0, 0.05);
  EXPECT_EQ(server.update(0.1, fromReference(server.sample(0.1))), ServerEvent::kNone);

  server.insertScan(server.sample(0.1).p_world_m, wallScan(3.0, 1.0));
  EXPECT_NE(server.lastMessage().find("collision predicted"), std::string::npos)
      << server.lastMessage();
  ASSERT_EQ(server.update(0.2, fromReference(server.sample(0.2))), ServerEvent::kReplanned);
  EXPECT_LT(LocalPlanner::firstCollisionTime(*server.current(), server.grid(), 0.0, 100.0), 0.0);
  // Goes around the wall, keeping the clearance from every wall point.
  double min_dist = 1e9;
  for (double t = 0; t <= server.current()->duration(); t += 0.01) {
    const Eigen::Vector3d p = server.current()->position(t);
    for (const auto& w : wallScan(3.0, 1.0))
      min_dist = std::min(min_dist, (w.cast<double>() - p).norm());
  }
  EXPECT_GT(min_dist, server.config().planner.corridor.clearance_m - 0.05);
  EXPECT_LT((server.current()->position(server.current()->duration()) - goal).norm(), 1e-6);
}

TEST(TrajectoryServer, FliesToTheGoalAndReportsIt) {
  TrajectoryServer server(smallConfig());
  server.setGoal({4, 3, 1.5}, std::nullopt, 0.0);
  VehicleState state = at({0, 0, 1});
  bool reached = false;
  int replans = 0;
  for (double t = 0.0; t < 20.0 && !reached; t += 0.01) {
    const ServerEvent e = server.update(t, state);
    ASSERT_NE(e, ServerEvent::kEmergencyStop) << server.lastMessage();
    replans += e == ServerEvent::kReplanned;
    reached = e == ServerEvent::kGoalReached;
    state = fromReference(server.sample(t));  // perfect tracking
  }
  EXPECT_TRUE(reached);
  EXPECT_FALSE(server.goal().has_value());
  EXPECT_GE(replans, 2);  // the period replans while flying
  EXPECT_LT(replans, 12);
  EXPECT_LT((state.p_world_m - Eigen::Vector3d(4, 3, 1.5)).norm(), 1e-3);
  EXPECT_EQ(server.update(30.0, state), ServerEvent::kNone);  // holds, no more plans
}

// The planner hands its target on at every update; only a new goal is a new question.
TEST(TrajectoryServer, AGoalRequestedAgainIsIgnoredUntilCleared) {
  TrajectoryServer server(smallConfig());
  const Eigen::Vector3d goal(4, 3, 1.5);
  EXPECT_EQ(server.setGoal(goal, std::nullopt, 0.0), ServerEvent::kNone);
  VehicleState state = at({0, 0, 1});
  ASSERT_EQ(server.update(0.0, state), ServerEvent::kReplanned) << server.lastMessage();
  const std::string message = server.lastMessage();
  // Asked again on the way: nothing changes, no replan is due.
  EXPECT_EQ(server.setGoal(goal, Eigen::Vector3d(9, 9, 1), 0.1), ServerEvent::kSameGoal);
  EXPECT_EQ(server.lastMessage(), message);
  state = fromReference(server.sample(0.1));
  EXPECT_EQ(server.update(0.1, state), ServerEvent::kNone);
  bool reached = false;
  for (double t = 0.1; t < 20.0 && !reached; t += 0.01) {
    reached = server.update(t, state) == ServerEvent::kGoalReached;
    state = fromReference(server.sample(t));
  }
  ASSERT_TRUE(reached);
  // Asked again once reached: the vehicle is not sent back to it.
  EXPECT_EQ(server.setGoal(goal, std::nullopt, 21.0), ServerEvent::kSameGoal);
  EXPECT_FALSE(server.goal().has_value());
  // A rejected request leaves the last one in place; after clearGoal the goal is new again.
  EXPECT_EQ(server.setGoal(Eigen::Vector3d::Constant(kNaN), std::nullopt, 21.0),
            ServerEvent::kRejectedInput);
  EXPECT_EQ(server.setGoal(goal, std::nullopt, 21.0), ServerEvent::kSameGoal);
  server.clearGoal(21.0);
  EXPECT_EQ(server.setGoal(goal, std::nullopt, 22.0), ServerEvent::kNone);
  ASSERT_TRUE(server.goal().has_value());
  EXPECT_LT((*server.goal() - goal).norm(), 1e-12);
  EXPECT_STREQ(toString(ServerEvent::kSameGoal), "same_goal");
}

TEST(TrajectoryServer, GoalBeyondTheWindowIsReachedInStages) {
  TrajectoryServer server(smallConfig());  // 14 m window: the goal is 9 m beyond its edge
  const Eigen::Vector3d goal(16, 4, 1);
  server.setGoal(goal, std::nullopt, 0.0);
  VehicleState state = at({0, 0, 1});
  bool reached = false;
  for (double t = 0.0; t < 40.0 && !reached; t += 0.01) {
    const ServerEvent e = server.update(t, state);
    ASSERT_NE(e, ServerEvent::kEmergencyStop) << server.lastMessage();
    if (e == ServerEvent::kReplanned) {
      // Every plan ends inside the window it was planned in.
      const Eigen::Vector3d end = server.current()->position(server.current()->duration());
      EXPECT_TRUE(server.grid().inWindow(end));
    }
    reached = e == ServerEvent::kGoalReached;
    state = fromReference(server.sample(t));
  }
  EXPECT_TRUE(reached);
  EXPECT_LT((state.p_world_m - goal).norm(), 1e-3);
  EXPECT_GE(server.replanCount(), 2);  // implied by the two checks above; stated for clarity
}

TEST(TrajectoryServer, GoalInsideAWallIsReachedAtTheNearestFreeCell) {
  TrajectoryServer server(smallConfig());
  server.insertScan({0, 0, 1}, wallScan(3.0, 1.5));
  const Eigen::Vector3d goal(3.0, 0.0, 1.0);  // on the wall
  server.setGoal(goal, std::nullopt, 0.0);
  VehicleState state = at({0, 0, 1});
  bool reached = false;
  for (double t = 0.0; t < 15.0 && !reached; t += 0.01) {
    const ServerEvent e = server.update(t, state);
    ASSERT_NE(e, ServerEvent::kEmergencyStop) << server.lastMessage();
    reached = e == ServerEvent::kGoalReached;
    state = fromReference(server.sample(t));
  }
  ASSERT_TRUE(reached);
  ASSERT_NE(server.lastPlan(), nullptr);
  EXPECT_TRUE(server.lastPlan()->goal_adjusted);
  // Stopped in front of the wall, outside its inflation, within the goal search radius.
  EXPECT_LT(state.p_world_m.x(), 3.0 - server.config().grid.inflation_radius_m + 0.05);
  EXPECT_LE((state.p_world_m - goal).norm(),
            server.config().planner.astar.goal_search_radius_m + 0.1);
  EXPECT_LT(LocalPlanner::firstCollisionTime(*server.current(), server.grid(), 0.0, 100.0), 0.0);
}

// A closed box of walls around (4, 0, 1) in an otherwise free, known grid.
void encloseFourZeroOne(LocalGrid& grid) {
  grid.recenter({0, 0, 1});
  grid.setAllFree();
  // A closed box of walls around (4, 0, 1).
  for (double x = 3.0; x <= 5.0 + 1e-9; x += 0.1)
    for (double y = -1.0; y <= 1.0 + 1e-9; y += 0.1)
      for (double z = -0.5; z <= 2.5; z += 0.1)
        if (std::abs(x - 3.0) < 1e-6 || std::abs(x - 5.0) < 1e-6 || std::abs(y + 1.0) < 1e-6 ||
            std::abs(y - 1.0) < 1e-6)
          grid.setOccupied({x, y, z});
  for (double x = 3.0; x <= 5.0 + 1e-9; x += 0.1)
    for (double y = -1.0; y <= 1.0 + 1e-9; y += 0.1) {
      grid.setOccupied({x, y, -0.45});
      grid.setOccupied({x, y, 2.45});
    }
}

// Hovering with a goal nobody can reach: every plan floods the window. The retries wait longer
// and longer (0.2, 0.4, 0.8, 1.6, 2 s ...) instead of one every 0.2 s; a goal elsewhere is
// planned at once.
TEST(TrajectoryServer, RetriesOfAnUnreachableGoalBackOff) {
  auto attempts = [](double max_backoff_s) {
    TrajectoryServerConfig cfg = smallConfig();
    cfg.max_retry_backoff_s = max_backoff_s;
    cfg.planner.astar.max_expansions = 20000;  // fail fast: the count of attempts is the point
    TrajectoryServer server(cfg);
    encloseFourZeroOne(server.mutableGrid());
    server.setGoal({0, 0, 1}, std::nullopt, 0.0);
    EXPECT_EQ(server.update(0.0, at({0, 0, 1})), ServerEvent::kReplanned);
    for (double t = 0.0; t < 1.0; t += 0.01) server.update(t, fromReference(server.sample(t)));
    server.setGoal({4, 0, 1}, std::nullopt, 1.0);
    const int before = server.replanCount();
    for (double t = 1.0; t < 9.0; t += 0.01) server.update(t, fromReference(server.sample(t)));
    const int tried = server.replanCount() - before;
    // Elsewhere, reachable: planned on the next update.
    server.setGoal({-3, 2, 1}, std::nullopt, 9.0);
    EXPECT_EQ(server.update(9.0, fromReference(server.sample(9.0))), ServerEvent::kReplanned);
    return tried;
  };
  const int with_backoff = attempts(2.0);
  EXPECT_LE(with_backoff, 8);
  EXPECT_GE(with_backoff, 4);
  // Contrast: no backoff beyond the first wait.
  EXPECT_GE(attempts(0.2), 30);
}

// A goal that fails give_up_after_failed_plans plans in a row is given up, once, for the
// exploration planner to choose another; a reachable goal never is, and another unreachable
// goal gets its own report.
TEST(TrajectoryServer, AGoalThatKeepsFailingIsGivenUpOnce) {
  TrajectoryServerConfig cfg = smallConfig();
  cfg.planner.astar.max_expansions = 20000;
  cfg.give_up_after_failed_plans = 3;
  TrajectoryServer server(cfg);
  encloseFourZeroOne(server.mutableGrid());
  server.setGoal({0, 0, 1}, std::nullopt, 0.0);
  double t = 0.0;
  for (; t < 3.0; t += 0.01) server.update(t, fromReference(server.sample(t)));
  EXPECT_FALSE(server.goalFailure()) << "a reachable goal is not given up";

  server.setGoal({4, 0, 1}, std::nullopt, t);
  std::vector<double> failures_at;
  uint64_t seen = 0;
  const double asked_s = t;
  for (; t < asked_s + 10.0; t += 0.01) {
    server.update(t, fromReference(server.sample(t)));
    if (server.goalFailure() && server.goalFailure()->sequence != seen) {
      seen = server.goalFailure()->sequence;
      failures_at.push_back(t);
    }
  }
  ASSERT_EQ(failures_at.size(), 1u) << "reported once, though the server keeps retrying";
  const GoalFailure& f = *server.goalFailure();
  EXPECT_EQ(f.sequence, 1u);
  EXPECT_TRUE(f.goal_world_m.isApprox(Eigen::Vector3d(4, 0, 1)));
  EXPECT_EQ(f.failed_plans, 3);
  EXPECT_EQ(f.status, PlanStatus::kGoalUnreachable) << f.message;
  EXPECT_FALSE(f.message.empty());
  // Three attempts with the backoff (0, 0.2, 0.6 s) instead of the planner's 10 s watchdog.
  EXPECT_LT(failures_at.front() - asked_s, 1.5);
  // The same goal asked again (a planner republishing its target) is not a new report.
  server.setGoal({4, 0, 1}, std::nullopt, t);
  for (const double t0 = t; t < t0 + 3.0; t += 0.01)
    server.update(t, fromReference(server.sample(t)));
  EXPECT_EQ(server.goalFailure()->sequence, 1u);
  // Another goal in the same enclosure: its own report, at its first failure (it is within
  // new_question_distance_m of the failed one, the same unreachable place asked again).
  server.setGoal({4, 0.5, 1}, std::nullopt, t);
  const int plans_before = server.replanCount();
  for (const double t0 = t; t < t0 + 5.0 && server.goalFailure()->sequence == 1u; t += 0.01)
    server.update(t, fromReference(server.sample(t)));
  EXPECT_EQ(server.goalFailure()->sequence, 2u);
  EXPECT_EQ(server.replanCount() - plans_before, 1);
  EXPECT_TRUE(server.goalFailure()->goal_world_m.isApprox(Eigen::Vector3d(4, 0.5, 1)));
  // A reachable goal elsewhere: planned, and nothing more is given up.
  server.setGoal({-3, 2, 1}, std::nullopt, t);
  for (const double t0 = t; t < t0 + 3.0; t += 0.01)
    server.update(t, fromReference(server.sample(t)));
  EXPECT_EQ(server.goalFailure()->sequence, 2u);
}

TEST(TrajectoryServer, AnEnclosedGoalKeepsTheClearCourseAndBrakesOnlyWhenItIsThreatened) {
  TrajectoryServer server(smallConfig());
  encloseFourZeroOne(server.mutableGrid());
  server.setGoal({0, 0, 1}, std::nullopt, 0.0);
  ASSERT_EQ(server.update(0.0, at({-2, 0, 1})), ServerEvent::kReplanned);
  for (double t = 0.0; t < 0.5; t += 0.01) server.update(t, fromReference(server.sample(t)));
  const ReferenceSample moving = server.sample(0.5);
  ASSERT_GT(moving.v_world_mps.norm(), 0.3);
  // The new goal cannot be planned: the current trajectory (checked, nothing predicted on it)
  // is kept rather than braking off it, and the plan is retried.
  const double course_start = server.currentStart_s();
  server.setGoal({4, 0, 1}, std::nullopt, 0.5);
  EXPECT_EQ(server.update(0.5, fromReference(moving)), ServerEvent::kPlanFailedKeptCourse);
  EXPECT_FALSE(server.stopping());
  EXPECT_EQ(server.currentStart_s(), course_start);
  EXPECT_NE(server.lastMessage().find("plan failed"), std::string::npos) << server.lastMessage();
  EXPECT_EQ(server.update(0.6, fromReference(server.sample(0.6))), ServerEvent::kNone);
  EXPECT_EQ(server.update(0.7, fromReference(server.sample(0.7))),
            ServerEvent::kPlanFailedKeptCourse);
  EXPECT_NE(server.lastMessage().find("retry after a failed plan"), std::string::npos)
      << server.lastMessage();
  EXPECT_EQ(server.currentStart_s(), course_start);
  // A wall across the kept course: now nothing safe remains to follow, so it brakes.
  const Eigen::Vector3d ahead = server.sample(0.75).p_world_m;
  ASSERT_LT(ahead.x(), -0.9);
  server.insertScan(ahead, wallScan(-0.5, 1.0));
  EXPECT_NE(server.lastMessage().find("collision predicted"), std::string::npos)
      << server.lastMessage();
  EXPECT_EQ(server.update(0.75, fromReference(server.sample(0.75))), ServerEvent::kEmergencyStop);
  EXPECT_TRUE(server.stopping());
  // Continuous position and velocity into the stop, then at rest.
  const ReferenceSample s0 = server.sample(server.currentStart_s());
  EXPECT_LT((s0.p_world_m - server.sample(server.currentStart_s() - 1e-7).p_world_m).norm(), 1e-5);
  EXPECT_LT((s0.v_world_mps - server.sample(server.currentStart_s() - 1e-7).v_world_mps).norm(),
            1e-5);
  EXPECT_LT(server.sample(5.0).v_world_mps.norm(), 1e-9);
  // Retries keep the same stop (no new event, no jump).
  const double stop_start = server.currentStart_s();
  EXPECT_EQ(server.update(2.0, fromReference(server.sample(2.0))), ServerEvent::kNone);
  EXPECT_EQ(server.currentStart_s(), stop_start);
  // A reachable goal again: planning resumes.
  server.setGoal({0, 2, 1}, std::nullopt, 2.5);
  EXPECT_EQ(server.update(2.5, fromReference(server.sample(2.5))), ServerEvent::kReplanned);
  EXPECT_FALSE(server.stopping());
}

TEST(TrajectoryServer, RejectsNonFiniteInputs) {
  TrajectoryServer server(smallConfig());
  EXPECT_EQ(server.setGoal({kNaN, 0, 1}, std::nullopt, 0.0), ServerEvent::kRejectedInput);
  EXPECT_NE(server.lastMessage().find("non-finite goal"), std::string::npos);
  EXPECT_FALSE(server.goal().has_value());
  server.setGoal({3, 0, 1}, std::nullopt, 0.0);
  EXPECT_EQ(server.setGoal({1, 0, 1}, Eigen::Vector3d(kNaN, 0, 0), 0.0),
            ServerEvent::kRejectedInput);
  ASSERT_TRUE(server.goal().has_value());
  EXPECT_EQ(*server.goal(), Eigen::Vector3d(3, 0, 1));  // the previous goal is kept
  EXPECT_EQ(server.update(kNaN, at({0, 0, 1})), ServerEvent::kRejectedInput);
  EXPECT_EQ(server.update(0.0, at({0, kNaN, 1})), ServerEvent::kRejectedInput);
  EXPECT_EQ(server.current(), nullptr);
  ASSERT_EQ(server.update(0.0, at({0, 0, 1})), ServerEvent::kReplanned);
  // A scan with a bad origin is refused, non-finite points are skipped.
  const size_t occupied = server.grid().occupiedCount();
  server.insertScan({kNaN, 0, 0}, wallScan(2.0, 0.5));
  EXPECT_NE(server.lastMessage().find("non-finite sensor origin"), std::string::npos);
  EXPECT_EQ(server.grid().occupiedCount(), occupied);
  std::vector<Eigen::Vector3f> pts = {{2.f, 0.f, 1.f},
                                      {std::numeric_limits<float>::quiet_NaN(), 0.f, 0.f}};
  server.insertScan({0, 0, 1}, pts);
  EXPECT_GT(server.grid().occupiedCount(), occupied);
  EXPECT_FALSE(server.sample(kNaN).valid);
}

TEST(TrajectoryServer, SampledReferenceStaysInCorridorAndLimits) {
  TrajectoryServerConfig cfg = smallConfig();
  TrajectoryServer server(cfg);
  server.insertScan({0, 0, 1}, wallScan(2.5, 1.5));
  server.setGoal({5.5, 0.5, 1}, std::nullopt, 0.0);
  ASSERT_EQ(server.update(0.0, at({0, 0, 1})), ServerEvent::kReplanned) << server.lastMessage();
  const PlanResult* plan = server.lastPlan();
  ASSERT_NE(plan, nullptr);
  ASSERT_TRUE(plan->ok());
  const double v_max = cfg.planner.optimizer.v_max_mps, a_max = cfg.planner.optimizer.a_max_mps2;
  double v_peak = 0.0;
  for (double t = 0.0; t <= server.current()->duration() + 0.5; t += 0.005) {
    const ReferenceSample s = server.sample(t);
    ASSERT_TRUE(s.valid);
    EXPECT_TRUE(insideUnion(plan->corridor.polytopes, s.p_world_m, 2e-3)) << "t = " << t;
    EXPECT_LE(s.v_world_mps.norm(), v_max * 1.02);
    EXPECT_LE(s.a_world_mps2.norm(), a_max + 1e-6);
    v_peak = std::max(v_peak, s.v_world_mps.norm());
  }
  EXPECT_GT(v_peak, 1.0);  // it really moved
}

TEST(TrajectoryServer, FarFromTheReferencePlansFromTheVehicle) {
  TrajectoryServer server(smallConfig());
  server.setGoal({5, 0, 1}, std::nullopt, 0.0);
  ASSERT_EQ(server.update(0.0, at({0, 0, 1})), ServerEvent::kReplanned);
  VehicleState kicked = fromReference(server.sample(1.0));
  kicked.p_world_m.y() += 1.5;
  kicked.v_world_mps.y() = 1.0;
  ASSERT_EQ(server.update(1.0, kicked), ServerEvent::kReplanned);
  EXPECT_NEAR(server.currentStart_s(), 1.0, 1e-12);
  EXPECT_LT((server.sample(1.0).p_world_m - kicked.p_world_m).norm(), 1e-9);
  EXPECT_LT((server.sample(1.0).v_world_mps - kicked.v_world_mps).norm(), 1e-9);
}

TEST(TrajectoryServer, ClearGoalBrakesToAHold) {
  TrajectoryServer server(smallConfig());
  server.setGoal({5, 0, 1}, std::nullopt, 0.0);
  ASSERT_EQ(server.update(0.0, at({0, 0, 1})), ServerEvent::kReplanned);
  const ReferenceSample mid = server.sample(1.0);
  server.clearGoal(1.0);
  EXPECT_FALSE(server.goal().has_value());
  EXPECT_LT((server.sample(1.0).p_world_m - mid.p_world_m).norm(), 1e-9);
  EXPECT_LT(server.sample(10.0).v_world_mps.norm(), 1e-9);
  EXPECT_EQ(server.update(10.0, fromReference(server.sample(10.0))), ServerEvent::kNone);
}

// Odometry lost mid-flight: the reference slows to a stop on the trajectory it was serving
// (every sample lies on the original path), within v / a_max, and resumes continuously.
TEST(TrajectoryServer, HoldAlongPathStopsOnTheCurrentTrajectoryAndResumes) {
  TrajectoryServer server(smallConfig());
  server.setGoal({5, 4, 1.5}, std::nullopt, 0.0);
  VehicleState state = at({0, 0, 1});
  double t = 0.0;
  for (; t < 1.5; t += 0.01) {
    server.update(t, state);
    state = fromReference(server.sample(t));
  }
  ASSERT_NE(server.current(), nullptr);
  const Trajectory original = *server.current();
  const double start = server.currentStart_s();
  const double speed0 = server.sample(t).v_world_mps.norm();
  ASSERT_GT(speed0, 1.0);
  server.holdAlongPath(t);
  ASSERT_TRUE(server.holdingAlongPath());
  EXPECT_EQ(server.update(t + 0.1, state), ServerEvent::kNone);  // no replanning meanwhile
  const double decel = server.config().planner.optimizer.a_max_mps2;
  double last_speed = speed0, tau = t - start;
  for (double h = t; h < t + speed0 / decel + 1.0; h += 0.01) {
    const ReferenceSample r = server.sample(h);
    // On the original path: the nearest original sample ahead of the last one is within 1 mm.
    double best = 1e9;
    for (double q = tau; q < tau + 0.05; q += 0.0005) {
      const double d = (original.position(q) - r.p_world_m).norm();
      if (d < best) {
        best = d;
        tau = std::max(tau, q);
      }
    }
    EXPECT_LT(best, 1e-3) << "h = " << h;
    EXPECT_LE(r.v_world_mps.norm(), last_speed + 1e-9);
    EXPECT_LE(r.a_world_mps2.norm(), decel + 3.0 * server.config().planner.optimizer.a_max_mps2);
    last_speed = r.v_world_mps.norm();
  }
  EXPECT_LT(last_speed, 1e-9);  // at rest after v / a
  const double t_back = t + speed0 / decel + 1.0;
  const ReferenceSample before = server.sample(t_back);
  server.resumeFromHold(t_back);
  EXPECT_FALSE(server.holdingAlongPath());
  EXPECT_LT((server.sample(t_back).p_world_m - before.p_world_m).norm(), 1e-6);
  EXPECT_EQ(server.update(t_back, fromReference(before)), ServerEvent::kReplanned);
}

TEST(TrajectoryServer, ConfigValidationNamesTheKey) {
  const auto expectKey = [](const TrajectoryServerConfig& c, const std::string& key) {
    efs::testing::expectConfigErrorNaming([&] { TrajectoryServer server(c); }, key);
  };
  TrajectoryServerConfig cfg;
  cfg.replan_period_s = 0.0;
  expectKey(cfg, "trajectory_server.replan_period_s");
  cfg = TrajectoryServerConfig();
  cfg.planner.optimizer.v_max_mps = kNaN;
  EXPECT_THROW(cfg.validate(), ConfigError);
  // A check clearance beyond the corridor's would flag every fresh plan.
  cfg = TrajectoryServerConfig();
  cfg.collision_check_clearance_m = cfg.planner.corridor.clearance_m + 0.1;
  expectKey(cfg, "collision_check_clearance_m");
  cfg = TrajectoryServerConfig();
  cfg.retry_after_failed_plan_s = -1.0;
  EXPECT_THROW(cfg.validate(), ConfigError);
  cfg = TrajectoryServerConfig();
  cfg.give_up_after_failed_plans = 0;
  expectKey(cfg, "give_up_after_failed_plans");
}

}  // namespace
}  // namespace efs::traj
