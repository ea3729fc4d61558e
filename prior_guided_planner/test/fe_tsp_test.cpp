// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "efs_common/angles.h"
#include "efs_common/config_check.h"
#include "prior_guided_planner/fe_tsp.h"

namespace efs::planner {
namespace {

std::vector<PlanViewpoint> randomViewpoints(int n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-30.0, 30.0), yaw(-M_PI, M_PI);
  std::vector<PlanViewpoint> v(n);
  for (int i = 0; i < n; ++i) v[i] = PlanViewpoint{i, {u(rng), u(rng), 1.0}, yaw(rng)};
  return v;
}

// Straight-line path lengths (the oracle would search the map).
PathLengthFn euclidean(const RobotPose& r, const std::vector<PlanViewpoint>& v) {
  return [r, v](int a, int b) {
    const Eigen::Vector3d pa = a == kRobotNode ? r.position_world_m : v[a].position_world_m;
    const Eigen::Vector3d pb = b == kRobotNode ? r.position_world_m : v[b].position_world_m;
    return (pa - pb).norm();
  };
}

TEST(FeTsp, CostMatrixFollowsThePaper) {
  RobotPose robot;
  robot.yaw_rad = 0.5;
  const auto v = randomViewpoints(3, 1);
  const auto L = euclidean(robot, v);
  const Eigen::Vector2d term(40.0, 0.0);
  FeTspConfig cfg;
  const CostMatrix c = buildFeTspMatrix(robot, v, {0, 1, 2}, {true, false, false}, term, L, cfg);
  ASSERT_EQ(c.size(), 6);
  const int t = 4, dv = 5;
  const double dyaw0 = std::abs(angleDiff(v[0].yaw_rad, 0.5)) / 4.0;
  EXPECT_NEAR(c(0, 1), std::max(L(kRobotNode, 0) / 4.0, dyaw0) - 0.2 * dyaw0, 1e-12);  // urgent
  const double dyaw1 = std::abs(angleDiff(v[1].yaw_rad, 0.5)) / 4.0;
  EXPECT_NEAR(c(0, 2), std::max(L(kRobotNode, 1) / 4.0, dyaw1), 1e-12);
  EXPECT_NEAR(c(1, 2), L(0, 1) / 4.0, 1e-12);
  EXPECT_NEAR(c(2, t), (v[1].position_world_m.head<2>() - term).norm() / 4.0, 1e-12);
  EXPECT_EQ(c(2, 0), 0.0);
  EXPECT_EQ(c(t, dv), 0.0);
  EXPECT_EQ(c(dv, 0), 0.0);
  for (int j = 1; j <= 3; ++j) {
    EXPECT_EQ(c(t, j), kUnreachable);
    EXPECT_EQ(c(dv, j), kUnreachable);
    EXPECT_EQ(c(j, dv), kUnreachable);
  }
  EXPECT_EQ(c(0, dv), kUnreachable);
  EXPECT_EQ(c(dv, t), kUnreachable);
  EXPECT_EQ(c(0, t), kUnreachable);
}

double bestOpenCost(const CostMatrix& c, int n) {
  std::vector<int> p(n);
  for (int i = 0; i < n; ++i) p[i] = i + 1;
  double best = kUnreachable;
  do {
    double s = c(0, p[0]);
    for (int k = 0; k + 1 < n; ++k) s += c(p[k], p[k + 1]);
    best = std::min(best, s + c(p.back(), n + 1));
  } while (std::next_permutation(p.begin(), p.end()));
  return best;
}

TEST(FeTsp, ToursStartAtTheRobotVisitEveryViewpointOnceAndEndAtTheTerminal) {
  for (int n : {1, 4, 7, 30, 80}) {
    RobotPose robot;
    const auto v = randomViewpoints(n, 10 + n);
    const auto L = euclidean(robot, v);
    std::vector<int> iso, target;
    for (int i = 0; i < n; ++i) (i % 3 == 0 ? iso : target).push_back(i);
    const Eigen::Vector2d term(60.0, 60.0);
    const LocalTour t = solveFeTsp(robot, v, iso, target, term, L, FeTspConfig{});
    EXPECT_TRUE(t.feasible);
    EXPECT_TRUE(t.has_terminal);
    std::vector<int> sorted = t.viewpoints;
    std::sort(sorted.begin(), sorted.end());
    std::vector<int> all(n);
    for (int i = 0; i < n; ++i) all[i] = i;
    EXPECT_EQ(sorted, all) << "n=" << n;
    // The cost is that of robot -> tour -> terminal on the FE-TSP matrix (cycle closure free).
    std::vector<int> sel = iso;
    sel.insert(sel.end(), target.begin(), target.end());
    std::vector<bool> isf(sel.size());
    for (size_t k = 0; k < sel.size(); ++k) isf[k] = k < iso.size();
    const CostMatrix c = buildFeTspMatrix(robot, v, sel, isf, term, L, FeTspConfig{});
    std::vector<int> node_of(n);
    for (size_t k = 0; k < sel.size(); ++k) node_of[sel[k]] = static_cast<int>(k) + 1;
    double cost = c(0, node_of[t.viewpoints.front()]);
    for (size_t k = 0; k + 1 < t.viewpoints.size(); ++k)
      cost += c(node_of[t.viewpoints[k]], node_of[t.viewpoints[k + 1]]);
    cost += c(node_of[t.viewpoints.back()], n + 1);
    EXPECT_NEAR(cost, t.cost_s, 1e-9);
    if (n <= 7) {
      EXPECT_NEAR(t.cost_s, bestOpenCost(c, n), 1e-9) << "n=" << n;
    }
  }
}

TEST(FeTsp, TerminalPullsTheTourEnd) {
  // Viewpoints on a line; the terminal far to the +x side: the tour must end at the +x end.
  RobotPose robot;
  std::vector<PlanViewpoint> v;
  for (int i = 0; i < 6; ++i) v.push_back(PlanViewpoint{i, {-10.0 + 4.0 * i, 0.0, 1.0}, 0.0});
  const LocalTour t = solveFeTsp(robot, v, {}, {0, 1, 2, 3, 4, 5}, Eigen::Vector2d(100, 0),
                                 euclidean(robot, v), {});
  EXPECT_EQ(t.viewpoints.back(), 5);
  const LocalTour back = solveFeTsp(robot, v, {}, {0, 1, 2, 3, 4, 5}, Eigen::Vector2d(-100, 0),
                                    euclidean(robot, v), {});
  EXPECT_EQ(back.viewpoints.back(), 0);
}

TEST(FeTsp, UrgencyMakesIsolatedViewpointsComeFirst) {
  // Two viewpoints at the same distance; the robot must turn pi/2 for both. The isolated one is
  // cheaper to start with through the (negative) urgency term.
  RobotPose robot;
  std::vector<PlanViewpoint> v = {PlanViewpoint{0, {0, 8, 1}, M_PI / 2},
                                  PlanViewpoint{1, {0, -8, 1}, M_PI / 2}};
  const auto L = euclidean(robot, v);
  EXPECT_EQ(solveFeTsp(robot, v, {1}, {0}, std::nullopt, L, {}).viewpoints.front(), 1);
  EXPECT_EQ(solveFeTsp(robot, v, {0}, {1}, std::nullopt, L, {}).viewpoints.front(), 0);
}

TEST(FeTsp, UnreachableViewpointsAreLeftOutAndReported) {
  RobotPose robot;
  const auto v = randomViewpoints(6, 3);
  const auto e = euclidean(robot, v);
  const PathLengthFn L = [e](int a, int b) { return (a == 2 || b == 2) ? kUnreachable : e(a, b); };
  const LocalTour t = solveFeTsp(robot, v, {0, 1}, {2, 3, 4, 5}, Eigen::Vector2d(5, 5), L, {});
  EXPECT_EQ(t.unreachable_viewpoints, std::vector<int>{2});
  EXPECT_EQ(t.viewpoints.size(), 5u);
  EXPECT_TRUE(t.feasible);
  const LocalTour pf = solvePriorFreeTour(robot, v, L, {});
  EXPECT_EQ(pf.unreachable_viewpoints, std::vector<int>{2});
  EXPECT_EQ(pf.viewpoints.size(), 5u);
  EXPECT_FALSE(pf.has_terminal);
}

TEST(FeTsp, PriorFreeVisitsAllAndIsOptimalOnSmallScenes) {
  RobotPose robot;
  const auto v = randomViewpoints(7, 5);
  const auto L = euclidean(robot, v);
  const LocalTour t = solvePriorFreeTour(robot, v, L, {});
  ASSERT_EQ(t.viewpoints.size(), 7u);
  std::vector<int> p(7);
  for (int i = 0; i < 7; ++i) p[i] = i;
  const CostMatrix c =
      buildFeTspMatrix(robot, v, p, std::vector<bool>(7, false), std::nullopt, L, {});
  double best = kUnreachable;
  do {
    double s = c(0, p[0] + 1);
    for (int k = 0; k + 1 < 7; ++k) s += c(p[k] + 1, p[k + 1] + 1);
    best = std::min(best, s);
  } while (std::next_permutation(p.begin(), p.end()));
  EXPECT_NEAR(t.cost_s, best, 1e-9);
  EXPECT_TRUE(solvePriorFreeTour(robot, {}, L, {}).viewpoints.empty());
}

// Two viewpoints at the same path length and yaw, one ahead of the moving robot, one behind.
TEST(FeTsp, MovingRobotPrefersTheViewpointAhead) {
  RobotPose robot;
  robot.position_world_m.z() = 1.0;
  robot.velocity_world_mps = Eigen::Vector3d(2.0, 0.0, 0.0);
  const std::vector<PlanViewpoint> v{{0, {-6.0, 0.0, 1.0}, 0.0}, {1, {6.0, 0.0, 1.0}, 0.0}};
  const auto L = euclidean(robot, v);
  FeTspConfig cfg;
  cfg.direction_change_cost_s_per_rad = 1.0;
  const CostMatrix c = buildFeTspMatrix(robot, v, {0, 1}, {false, false}, std::nullopt, L, cfg);
  EXPECT_NEAR(c(0, 2), 6.0 / 4.0, 1e-12);         // straight ahead: no extra cost
  EXPECT_NEAR(c(0, 1), 6.0 / 4.0 + M_PI, 1e-12);  // turning round: pi rad
  EXPECT_EQ(solvePriorFreeTour(robot, v, L, cfg).viewpoints.front(), 1);

  robot.velocity_world_mps = Eigen::Vector3d(-2.0, 0.0, 0.0);
  EXPECT_EQ(solvePriorFreeTour(robot, v, L, cfg).viewpoints.front(), 0);
}

TEST(FeTsp, HoveringGuidedOrPaperCostsHaveNoDirectionTerm) {
  RobotPose robot;
  robot.position_world_m.z() = 1.0;
  const std::vector<PlanViewpoint> v{{0, {-6.0, 0.0, 1.0}, 0.0}, {1, {0.0, 6.0, 1.0}, 0.0}};
  const auto L = euclidean(robot, v);
  FeTspConfig cfg;
  cfg.direction_change_cost_s_per_rad = 1.0;
  robot.velocity_world_mps = Eigen::Vector3d(0.3, 0.0, 0.0);  // below direction_min_speed_mps
  const CostMatrix hovering = buildFeTspMatrix(robot, v, {0, 1}, {false, false}, {}, L, cfg);
  EXPECT_NEAR(hovering(0, 1), 1.5, 1e-12);
  EXPECT_NEAR(hovering(0, 2), 1.5, 1e-12);
  robot.velocity_world_mps = Eigen::Vector3d(3.0, 0.0, 0.0);
  cfg.direction_change_cost_s_per_rad = 0.0;
  const CostMatrix paper = buildFeTspMatrix(robot, v, {0, 1}, {false, false}, {}, L, cfg);
  EXPECT_NEAR(paper(0, 1), 1.5, 1e-12);
  EXPECT_NEAR(paper(0, 2), 1.5, 1e-12);
  robot.velocity_world_mps = Eigen::Vector3d(3.0, 0.0, 0.0);
  const Eigen::Vector2d terminal(0.0, 30.0);  // the guidance sets the direction
  const CostMatrix guided = buildFeTspMatrix(robot, v, {0, 1}, {false, false}, terminal, L, cfg);
  EXPECT_NEAR(guided(0, 1), 1.5, 1e-12);
  EXPECT_NEAR(guided(0, 2), 1.5, 1e-12);
  robot.velocity_world_mps = Eigen::Vector3d(std::nan(""), 0.0, 0.0);  // never NaN costs
  cfg.direction_change_cost_s_per_rad = 1.0;
  const CostMatrix unknown = buildFeTspMatrix(robot, v, {0, 1}, {false, false}, {}, L, cfg);
  EXPECT_NEAR(unknown(0, 2), 1.5, 1e-12);
}

// The time to turn the velocity towards a viewpoint at the acceleration limit: nothing straight
// ahead at full speed, 4 * sqrt(2) / a at a right angle, 2 * 4 / a to turn back.
TEST(FeTsp, VelocityChangeCostIsTheTimeToTurnTheVelocity) {
  RobotPose robot;
  robot.position_world_m.z() = 1.0;
  robot.velocity_world_mps = Eigen::Vector3d(4.0, 0.0, 0.5);  // climbing does not count
  const std::vector<PlanViewpoint> v{
      {0, {6.0, 0.0, 1.0}, 0.0}, {1, {0.0, 6.0, 1.0}, 0.0}, {2, {-6.0, 0.0, 1.0}, 0.0}};
  const auto L = euclidean(robot, v);
  FeTspConfig cfg;
  cfg.velocity_change_accel_mps2 = 6.0;
  const std::vector<int> all{0, 1, 2};
  const std::vector<bool> none(3, false);
  const CostMatrix c = buildFeTspMatrix(robot, v, all, none, std::nullopt, L, cfg);
  EXPECT_NEAR(c(0, 1), 1.5, 1e-12);
  EXPECT_NEAR(c(0, 2), 1.5 + 4.0 * std::sqrt(2.0) / 6.0, 1e-12);
  EXPECT_NEAR(c(0, 3), 1.5 + 8.0 / 6.0, 1e-12);
  EXPECT_NEAR(c(1, 3), 12.0 / 4.0, 1e-12);  // only the first leg starts from the robot's motion
  EXPECT_EQ(solvePriorFreeTour(robot, v, L, cfg).viewpoints.front(), 0);
  // Hovering, every direction costs the same: the time to reach full speed.
  robot.velocity_world_mps.setZero();
  const CostMatrix hovering = buildFeTspMatrix(robot, v, all, none, std::nullopt, L, cfg);
  for (int k = 1; k <= 3; ++k) EXPECT_NEAR(hovering(0, k), 1.5 + 4.0 / 6.0, 1e-12);
  // A guided tour keeps the paper's costs: its terminal gives the direction.
  robot.velocity_world_mps = Eigen::Vector3d(4.0, 0.0, 0.0);
  const Eigen::Vector2d terminal(0.0, 30.0);
  const CostMatrix guided = buildFeTspMatrix(robot, v, all, none, terminal, L, cfg);
  for (int k = 1; k <= 3; ++k) EXPECT_NEAR(guided(0, k), 1.5, 1e-12);
  // An unknown velocity adds nothing rather than NaN.
  robot.velocity_world_mps = Eigen::Vector3d(std::nan(""), 0.0, 0.0);
  const CostMatrix unknown = buildFeTspMatrix(robot, v, all, none, std::nullopt, L, cfg);
  for (int k = 1; k <= 3; ++k) EXPECT_NEAR(unknown(0, k), 1.5, 1e-12);
}

// Viewpoints on a line, 8 on each side of a hovering robot: west first or east first cost the
// same. The warm start (the last tour) decides, and a warm start worse than the optimum is
// improved, not kept.
TEST(FeTsp, AWarmStartKeepsAnEquallyGoodOrderAndImprovesAWorseOne) {
  RobotPose robot;
  robot.position_world_m = Eigen::Vector3d(0.0, 0.0, 1.0);
  std::vector<PlanViewpoint> v;
  for (int k = 1; k <= 8; ++k) {
    v.push_back({100 + k, {-2.0 * k, 0.0, 1.0}, 0.0});  // west, ids 101..108
    v.push_back({200 + k, {2.0 * k, 0.0, 1.0}, 0.0});   // east, ids 201..208
  }
  const auto L = euclidean(robot, v);
  const FeTspConfig cfg;
  ASSERT_GT(static_cast<int>(v.size()) + 1, cfg.atsp.exact_max_nodes);  // the heuristic solver
  const double best_s = (16.0 + 32.0) / cfg.v_max_mps;  // 16 m one way, 32 m back and across
  std::vector<int> west_first, east_first, zigzag;
  for (int k = 1; k <= 8; ++k) west_first.push_back(100 + k), east_first.push_back(200 + k);
  for (int k = 1; k <= 8; ++k) west_first.push_back(200 + k), east_first.push_back(100 + k);
  for (int k = 1; k <= 8; ++k) zigzag.push_back(100 + k), zigzag.push_back(200 + k);
  const auto firstX = [&](const LocalTour& t) {
    return v[t.viewpoints.front()].position_world_m.x();
  };

  const LocalTour w = solvePriorFreeTour(robot, v, L, cfg, &west_first);
  const LocalTour e = solvePriorFreeTour(robot, v, L, cfg, &east_first);
  ASSERT_EQ(w.viewpoints.size(), v.size());
  ASSERT_EQ(e.viewpoints.size(), v.size());
  EXPECT_NEAR(w.cost_s, best_s, 1e-9);
  EXPECT_NEAR(e.cost_s, best_s, 1e-9);
  EXPECT_LT(firstX(w), 0.0);
  EXPECT_GT(firstX(e), 0.0);
  // Ids no longer present are skipped, and the rest still come after them.
  std::vector<int> stale = east_first;
  stale.insert(stale.begin(), 999);
  EXPECT_GT(firstX(solvePriorFreeTour(robot, v, L, cfg, &stale)), 0.0);
  // None of them present: the same tour as without a warm start.
  const std::vector<int> gone{998, 999};
  EXPECT_EQ(solvePriorFreeTour(robot, v, L, cfg, &gone).viewpoints,
            solvePriorFreeTour(robot, v, L, cfg).viewpoints);
  const LocalTour z = solvePriorFreeTour(robot, v, L, cfg, &zigzag);
  EXPECT_NEAR(z.cost_s, best_s, 1e-9);
  // The FE-TSP with a terminal: the warm start ends at G_t, and the tour stays valid.
  const Eigen::Vector2d terminal(20.0, 0.0);
  std::vector<int> all(v.size());
  for (size_t k = 0; k < v.size(); ++k) all[k] = static_cast<int>(k);
  const LocalTour g = solveFeTsp(robot, v, {}, all, terminal, L, cfg, &zigzag);
  EXPECT_TRUE(g.feasible);
  EXPECT_EQ(g.viewpoints.size(), v.size());
  EXPECT_LT(firstX(g), 0.0);  // west first, ending east towards the terminal
}

TEST(FeTsp, ConfigValidationNamesTheKey) {
  FeTspConfig cfg;
  cfg.v_max_mps = 0.0;
  try {
    cfg.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("fe_tsp.v_max_mps"), std::string::npos);
  }
  cfg = FeTspConfig();
  cfg.beta_e = std::nan("");
  EXPECT_THROW(cfg.validate(), ConfigError);
  cfg = FeTspConfig();
  EXPECT_DOUBLE_EQ(cfg.beta_e, -0.2);
  EXPECT_DOUBLE_EQ(cfg.omega_max_radps, 4.0);
  EXPECT_DOUBLE_EQ(cfg.direction_change_cost_s_per_rad, 0.0);  // the paper's costs
  cfg.direction_change_cost_s_per_rad = -1.0;
  try {
    cfg.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("direction_change_cost_s_per_rad"), std::string::npos);
  }
  cfg = FeTspConfig();
  EXPECT_DOUBLE_EQ(cfg.velocity_change_accel_mps2, 0.0);  // the paper's costs
  cfg.velocity_change_accel_mps2 = std::nan("");
  try {
    cfg.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("velocity_change_accel_mps2"), std::string::npos);
  }
}

}  // namespace
}  // namespace efs::planner
