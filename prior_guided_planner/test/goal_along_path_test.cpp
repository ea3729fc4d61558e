// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/goal_along_path.h"

#include <gtest/gtest.h>

#include <limits>

namespace efs::planner {
namespace {

const auto kAnywhere = [](const Eigen::Vector3d&) { return true; };
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(GoalAlongPath, StopsAtTheLookAheadLengthAndTheReach) {
  const std::vector<Eigen::Vector3d> path = {{0, 0, 0}, {3, 0, 0}, {3, 10, 0}};
  EXPECT_TRUE(goalAlongPath(path, 5.0, 3.0, kAnywhere).isApprox(Eigen::Vector3d(3, 2, 0)));
  EXPECT_TRUE(goalAlongPath(path, kInf, kInf, kAnywhere).isApprox(Eigen::Vector3d(3, 10, 0)));
  // Within 5 m of the start: the last point of the corner leg inside that circle, y = 4.
  const auto near = [](const Eigen::Vector3d& p) { return p.norm() <= 5.0 + 1e-9; };
  EXPECT_TRUE(goalAlongPath(path, kInf, kInf, near).isApprox(Eigen::Vector3d(3, 4, 0), 1e-9));
  // Out of reach at once: the start itself.
  EXPECT_TRUE(goalAlongPath(path, kInf, kInf, [](const Eigen::Vector3d& p) {
                return p.x() < 0.05;
              }).isApprox(Eigen::Vector3d::Zero()));
}

// Past the first viewpoint (3 m along) the path turns back toward the start: the goal stays at
// the turn instead of coming back beside the robot; before the first viewpoint the same turn
// is followed (a detour the searched path needs).
TEST(GoalAlongPath, DoesNotComeBackTowardTheRobotPastTheFirstViewpoint) {
  const std::vector<Eigen::Vector3d> back = {{0, 0, 0}, {3, 0, 0}, {4, 0, 0}, {0.5, 0.5, 0}};
  EXPECT_LT((goalAlongPath(back, 8.0, 3.0, kAnywhere) - Eigen::Vector3d(4, 0, 0)).norm(), 0.15);
  const Eigen::Vector3d followed = goalAlongPath(back, 8.0, kInf, kAnywhere);
  EXPECT_LT(followed.x(), 1.0);  // without the rule: 8 m along, back beside the start
  EXPECT_THROW(goalAlongPath({}, 1.0, 1.0, kAnywhere), std::invalid_argument);
}

}  // namespace
}  // namespace efs::planner
