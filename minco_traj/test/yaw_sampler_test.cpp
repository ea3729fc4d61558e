// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include "efs_common/angles.h"
#include "efs_common/config_check.h"
#include "minco_traj/minco.h"
#include "minco_traj/trajectory.h"
#include "minco_traj/yaw_planner.h"

namespace efs::traj {
namespace {

void expectWithinLimits(const YawProfile& prof, const YawPlannerConfig& cfg) {
  double y, r, a;
  const double dur = prof.duration();
  for (double t = 0; t <= dur + 0.5; t += 0.001) {
    prof.sample(t, &y, &r, &a);
    EXPECT_LE(std::abs(r), cfg.yaw_rate_max_radps + 1e-9) << t;
    EXPECT_LE(std::abs(a), cfg.yaw_acc_max_radps2 + 1e-9) << t;
  }
  // Yaw is continuous (no jumps between segments).
  double prev;
  prof.sample(0, &prev, nullptr, nullptr);
  for (double t = 0.001; t <= dur; t += 0.001) {
    prof.sample(t, &y, nullptr, nullptr);
    EXPECT_LT(std::abs(y - prev), cfg.yaw_rate_max_radps * 0.001 + 1e-9);
    prev = y;
  }
}

TEST(YawPlanner, ReachesTargetTheShortWayWithinLimits) {
  YawPlannerConfig cfg;
  YawPlanner yp(cfg);
  struct Case {
    double y0, r0, target;
  };
  for (const Case& c : {Case{0, 0, 3.0}, Case{3.0, 0, -3.0}, Case{0, 3.9, -1.0}, Case{0, -4.0, 0.1},
                        Case{1.0, 0, 1.0}, Case{0, 0, 0.05}}) {
    const YawProfile prof = yp.plan(c.y0, c.r0, c.target);
    expectWithinLimits(prof, cfg);
    double y, r, a;
    prof.sample(prof.duration() + 1.0, &y, &r, &a);
    EXPECT_NEAR(angleDiff(y, c.target), 0.0, 1e-9) << c.y0 << " -> " << c.target;
    EXPECT_NEAR(r, 0.0, 1e-9);
    prof.sample(0, &y, &r, &a);
    EXPECT_NEAR(y, c.y0, 1e-12);
    EXPECT_NEAR(r, c.r0, 1e-12);
  }
  // 3 -> -3 rad goes the short way (0.28 rad across pi), so it is quick.
  EXPECT_LT(yp.plan(3.0, 0, -3.0).duration(), 1.0);
  // A half turn at 4 rad/s and 4 rad/s^2: accelerate 1 s (2 rad), then ... triangular profile.
  EXPECT_NEAR(yp.plan(0, 0, M_PI - 1e-9).duration(), 2.0 * std::sqrt(M_PI / 4.0), 1e-6);
}

TEST(YawPlanner, LookAtYaw) {
  EXPECT_NEAR(YawPlanner::lookAtYaw({0, 0, 0}, {0, 2, 5}, 0.3), M_PI / 2, 1e-12);
  EXPECT_NEAR(YawPlanner::lookAtYaw({1, 1, 0}, {1, 1, 5}, 0.3), 0.3, 1e-12);
  YawPlannerConfig c;
  c.yaw_rate_max_radps = 0;
  EXPECT_THROW(c.validate(), ConfigError);
}

TEST(Trajectory, SampleIsConsistentWithNumericalDerivatives) {
  MincoS3 m;
  Eigen::Matrix3d head = Eigen::Matrix3d::Zero(), tail = Eigen::Matrix3d::Zero();
  head.col(0) << 0, 0, 1;
  tail.col(0) << 4, 2, 1;
  m.setConditions(head, tail, 3);
  Eigen::Matrix3Xd q(3, 2);
  q << 1, 3, 0.5, 1.5, 1.2, 1.1;
  Eigen::VectorXd T(3);
  T << 1.0, 1.2, 0.9;
  m.setParameters(q, T);
  Trajectory tr = m.toTrajectory();
  tr.setYaw(YawPlanner().plan(0.0, 0.0, 1.0));
  const double h = 1e-5;
  for (double t = 0.05; t < tr.duration() - 0.05; t += 0.13) {
    const TrajectoryPoint p = tr.sample(t), pp = tr.sample(t + h), pm = tr.sample(t - h);
    EXPECT_LT(((pp.p_world_m - pm.p_world_m) / (2 * h) - p.v_world_mps).norm(), 1e-6);
    EXPECT_LT(((pp.v_world_mps - pm.v_world_mps) / (2 * h) - p.a_world_mps2).norm(), 1e-5);
    EXPECT_LT(((pp.a_world_mps2 - pm.a_world_mps2) / (2 * h) - p.j_world_mps3).norm(), 1e-4);
    EXPECT_NEAR((pp.yaw_rad - pm.yaw_rad) / (2 * h), p.yaw_rate_radps, 1e-4);
  }
  // Beyond the end: final position held at rest.
  const TrajectoryPoint end = tr.sample(tr.duration() + 5.0);
  EXPECT_LT((end.p_world_m - tail.col(0)).norm(), 1e-9);
  EXPECT_EQ(end.v_world_mps.norm(), 0.0);
  EXPECT_NEAR(end.yaw_rad, 1.0, 1e-9);
  EXPECT_EQ(tr.sample(-1.0).p_world_m, tr.position(0));
}

TEST(Trajectory, EmergencyStopBrakesAtTheLimit) {
  const Eigen::Vector3d p(1, 2, 3), v(3, 0, -1);
  const double decel = 6.0;
  const Trajectory tr = emergencyStop(p, v, decel, 0.7);
  const double t_stop = v.norm() / decel;
  EXPECT_NEAR(tr.durations()[0], t_stop, 1e-12);
  EXPECT_LT(tr.velocity(t_stop).norm(), 1e-9);
  EXPECT_NEAR((tr.position(t_stop + 0.5) - p).norm(), v.squaredNorm() / (2 * decel), 1e-9);
  double prev = v.norm();
  for (double t = 0.01; t < tr.duration(); t += 0.01) {
    const double s = tr.velocity(t).norm();
    EXPECT_LE(s, prev + 1e-12);
    EXPECT_LE(tr.acceleration(t).norm(), decel + 1e-9);
    prev = s;
  }
  EXPECT_NEAR(tr.sample(0.1).yaw_rad, 0.7, 1e-12);
  // At rest already: just a hold.
  const Trajectory hold = emergencyStop(p, Eigen::Vector3d::Zero(), decel, 0.0);
  EXPECT_EQ(hold.pieceCount(), 1);
  EXPECT_EQ(hold.position(0.5), p);
  EXPECT_THROW(emergencyStop(p, v, 0.0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace efs::traj
