// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <random>

#include "efs_common/config_check.h"
#include "minco_traj/lbfgs.h"
#include "minco_traj/minco.h"
#include "minco_traj/traj_optimizer.h"

namespace efs::traj {
namespace {

Eigen::Matrix3d pva(const Eigen::Vector3d& p, const Eigen::Vector3d& v, const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << p, v, a;
  return m;
}

TEST(BandedSystem, SolvesLikeDenseLu) {
  // A MINCO matrix is a realistic banded system; compare against Eigen's dense LU.
  MincoS3 m;
  const int n = 5;
  m.setConditions(pva({0, 0, 0}, {1, 0, 0}, {0, 0, 0}), pva({5, 1, 1}, {0, 0, 0}, {0, 0, 0}), n);
  Eigen::Matrix3Xd q(3, n - 1);
  q << 1, 2, 3, 4, 0.5, -0.5, 0.2, 1, 0, 0.3, 0.6, 0.9;
  Eigen::VectorXd T(n);
  T << 0.7, 1.1, 0.9, 1.3, 0.8;
  m.setParameters(q, T);
  // Rebuild the trajectory and check that the coefficients satisfy every equation directly.
  const Trajectory tr = m.toTrajectory();
  EXPECT_NEAR((tr.position(0) - Eigen::Vector3d(0, 0, 0)).norm(), 0, 1e-9);
  EXPECT_NEAR((tr.velocity(0) - Eigen::Vector3d(1, 0, 0)).norm(), 0, 1e-9);

  BandedSystem b;
  b.create(8, 2);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(8, 8);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 8; ++i)
    for (int j = std::max(0, i - 2); j <= std::min(7, i + 2); ++j) {
      const double v = (i == j) ? 5.0 + u(rng) : u(rng);
      b(i, j) = v;
      dense(i, j) = v;
    }
  b.factorize();
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(8, 3), x = rhs, xt = rhs;
  b.solve(x);
  b.solveTranspose(xt);
  EXPECT_LT((dense * x - rhs).norm(), 1e-10);
  EXPECT_LT((dense.transpose() * xt - rhs).norm(), 1e-10);
}

class MincoFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    n = 6;
    head = pva({0, 0, 1}, {1.0, -0.5, 0.2}, {0.3, 0.1, -0.2});
    tail = pva({8, 3, 2}, {0.5, 0, 0}, {0, 0.2, 0});
    q.resize(3, n - 1);
    for (int i = 0; i < n - 1; ++i)
      q.col(i) = Eigen::Vector3d(1.3 * (i + 1), 0.5 * std::sin(i), 1.0 + 0.2 * i);
    T.resize(n);
    T << 0.8, 1.2, 0.6, 1.5, 0.9, 1.1;
    m.setConditions(head, tail, n);
    m.setParameters(q, T);
  }
  int n;
  Eigen::Matrix3d head, tail;
  Eigen::Matrix3Xd q;
  Eigen::VectorXd T;
  MincoS3 m;
};

TEST_F(MincoFixture, BoundaryConditionsAndWaypoints) {
  const Trajectory tr = m.toTrajectory();
  for (int d = 0; d < 3; ++d) {
    EXPECT_LT((tr.derivative(0.0, d) - head.col(d)).norm(), 1e-9) << "head derivative " << d;
    EXPECT_LT((tr.derivative(tr.duration(), d) - tail.col(d)).norm(), 1e-8) << "tail " << d;
  }
  double t = 0;
  for (int i = 0; i < n - 1; ++i) {
    t += T(i);
    EXPECT_LT((Trajectory::evalPiece(tr.pieces()[i], T(i), 0) - q.col(i)).norm(), 1e-9);
  }
}

TEST_F(MincoFixture, ContinuityOfPositionToJerkAndSnapAtJoints) {
  const Trajectory tr = m.toTrajectory();
  for (int i = 0; i < n - 1; ++i)
    for (int d = 0; d <= 4; ++d) {
      const Eigen::Vector3d left = Trajectory::evalPiece(tr.pieces()[i], T(i), d);
      const Eigen::Vector3d right = Trajectory::evalPiece(tr.pieces()[i + 1], 0.0, d);
      EXPECT_LT((left - right).norm(), 1e-7 * std::max(1.0, left.norm()))
          << "joint " << i << " derivative " << d;
    }
}

TEST(Minco, OnePieceIsTheKnownMinimumJerkPolynomial) {
  MincoS3 one;
  one.setConditions(pva({0, 0, 0}, {0, 0, 0}, {0, 0, 0}), pva({1, 0, 0}, {0, 0, 0}, {0, 0, 0}), 1);
  Eigen::Matrix3Xd q0(3, 0);
  Eigen::VectorXd T1(1);
  T1 << 1.0;
  one.setParameters(q0, T1);
  // Rest-to-rest minimum jerk: x(t) = 10 t^3 - 15 t^4 + 6 t^5, energy = 720.
  const PieceCoeffs c = one.piece(0);
  EXPECT_NEAR(c(0, 3), 10.0, 1e-9);
  EXPECT_NEAR(c(0, 4), -15.0, 1e-9);
  EXPECT_NEAR(c(0, 5), 6.0, 1e-9);
  EXPECT_NEAR(one.energy(), 720.0, 1e-7);
}

TEST_F(MincoFixture, EnergyGradientMatchesFiniteDifferences) {
  auto energyOf = [&](const Eigen::Matrix3Xd& qq, const Eigen::VectorXd& TT) {
    MincoS3 mm;
    mm.setConditions(head, tail, n);
    mm.setParameters(qq, TT);
    return mm.energy();
  };
  Eigen::MatrixXd gc = Eigen::MatrixXd::Zero(6 * n, 3);
  Eigen::VectorXd gT = Eigen::VectorXd::Zero(n), gTt;
  Eigen::Matrix3Xd gq;
  m.addEnergyGrad(gc, gT);
  m.propagateGrad(gc, gT, gq, gTt);
  const double h = 1e-6;
  for (int i = 0; i < n - 1; ++i)
    for (int a = 0; a < 3; ++a) {
      Eigen::Matrix3Xd qp = q, qm = q;
      qp(a, i) += h;
      qm(a, i) -= h;
      const double fd = (energyOf(qp, T) - energyOf(qm, T)) / (2 * h);
      EXPECT_NEAR(gq(a, i), fd, 1e-5 * std::max(1.0, std::abs(fd))) << "q " << a << "," << i;
    }
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd Tp = T, Tm = T;
    Tp(i) += h;
    Tm(i) -= h;
    const double fd = (energyOf(q, Tp) - energyOf(q, Tm)) / (2 * h);
    EXPECT_NEAR(gTt(i), fd, 1e-5 * std::max(1.0, std::abs(fd))) << "T " << i;
  }
}

std::vector<Polytope> boxCorridor() {
  // Two overlapping boxes forming an L: x in [-1, 6] x y in [-1, 1]; x in [4, 6] x y in [-1, 6].
  auto box = [](Eigen::Vector3d lo, Eigen::Vector3d hi, Eigen::Vector3d sa, Eigen::Vector3d sb) {
    Polytope p;
    p.A.resize(6, 3);
    p.b.resize(6);
    for (int a = 0; a < 3; ++a) {
      p.A.row(2 * a) = Eigen::Vector3d::Unit(a).transpose();
      p.b(2 * a) = hi[a];
      p.A.row(2 * a + 1) = -Eigen::Vector3d::Unit(a).transpose();
      p.b(2 * a + 1) = -lo[a];
    }
    p.seed_start_m = sa;
    p.seed_end_m = sb;
    return p;
  };
  return {box({-1, -1, 0}, {6, 1, 2}, {0, 0, 1}, {5, 0, 1}),
          box({4, -1, 0}, {6, 6, 2}, {5, 0, 1}, {5, 5, 1})};
}

TEST(MincoCorridorCost, GradientMatchesFiniteDifferencesWithActivePenalties) {
  TrajOptConfig cfg;
  cfg.v_max_mps = 1.0;  // make velocity and acceleration penalties active
  cfg.a_max_mps2 = 1.0;
  cfg.smoothing_eps = 1e-1;
  const auto corridor = boxCorridor();
  const std::vector<int> pp = {0, 0, 1, 1};
  MincoCorridorCost cost(cfg, pva({0, 0, 1}, {0.5, 0, 0}, {0, 0, 0}),
                         pva({5, 5, 1}, {0, 0, 0}, {0, 0, 0}), corridor, pp);
  Eigen::Matrix3Xd q(3, 3);
  q << 2.5, 5.6, 5.3, 0.9, -0.2, 2.5, 1, 1.5, 1;  // the second point pokes out of the corridor
  Eigen::VectorXd T(4);
  T << 1.5, 1.0, 1.2, 1.4;
  const Eigen::VectorXd x = cost.pack(q, T);
  Eigen::VectorXd g, gtmp;
  cost(x, g);
  const double h = 1e-6;
  for (int k = 0; k < x.size(); ++k) {
    Eigen::VectorXd xp = x, xm = x;
    xp(k) += h;
    xm(k) -= h;
    const double fd = (cost(xp, gtmp) - cost(xm, gtmp)) / (2 * h);
    EXPECT_NEAR(g(k), fd, 1e-4 * std::max(1.0, std::abs(fd))) << "component " << k;
  }
}

TEST(TrajOptimizer, RespectsLimitsAndStaysInCorridor) {
  TrajOptConfig cfg;
  TrajOptimizer opt(cfg);
  const auto corridor = boxCorridor();
  const auto res = opt.optimize(pva({0, 0, 1}, {0, 0, 0}, {0, 0, 0}),
                                pva({5, 5, 1}, {0, 0, 0}, {0, 0, 0}), corridor);
  ASSERT_TRUE(res.ok()) << res.message;
  const Trajectory& tr = res.trajectory;
  EXPECT_LE(tr.maxSpeed(0.002), cfg.v_max_mps * 1.02);
  EXPECT_LE(tr.maxAcceleration(0.002), cfg.a_max_mps2);
  for (double t = 0; t <= tr.duration(); t += 0.005) {
    const Eigen::Vector3d p = tr.position(t);
    EXPECT_TRUE(corridor[0].contains(p, 1e-3) || corridor[1].contains(p, 1e-3)) << t;
  }
  EXPECT_LT((tr.position(tr.duration()) - Eigen::Vector3d(5, 5, 1)).norm(), 1e-6);
  // Time pressure: a path of 10 m at <= 4 m/s and 6 m/s^2 takes at least 10/4 + 4/6 s.
  EXPECT_GT(tr.duration(), 10.0 / 4.0);
  EXPECT_LT(tr.duration(), 8.0);
}

// The state an emergency brake hands over: decelerating at exactly a_max. The plan cannot start
// below the limit, so the check measures it against what the head already has.
TEST(TrajOptimizer, PlansOnFromABrakeAtTheAccelerationLimit) {
  TrajOptConfig cfg;
  TrajOptimizer opt(cfg);
  const auto corridor = boxCorridor();
  const auto res = opt.optimize(pva({1, 0, 1}, {2.0, 0, 0}, {-cfg.a_max_mps2, 0, 0}),
                                pva({5, 5, 1}, {0, 0, 0}, {0, 0, 0}), corridor);
  ASSERT_TRUE(res.ok()) << res.message;
  EXPECT_NEAR(res.trajectory.acceleration(0.0).norm(), cfg.a_max_mps2, 1e-9);
  EXPECT_LE(res.feasibility.max_acceleration_mps2,
            cfg.a_max_mps2 * (1.0 + cfg.acceleration_tolerance));
}

TEST(TrajOptimizer, RefusesBadInput) {
  TrajOptimizer opt;
  const auto corridor = boxCorridor();
  auto res = opt.optimize(pva({20, 0, 1}, {0, 0, 0}, {0, 0, 0}),
                          pva({5, 5, 1}, {0, 0, 0}, {0, 0, 0}), corridor);
  EXPECT_EQ(res.status, TrajOptStatus::kBadInput);
  EXPECT_TRUE(res.trajectory.empty());
  res =
      opt.optimize(pva({0, 0, 1}, {0, 0, 0}, {0, 0, 0}), pva({5, 5, 1}, {0, 0, 0}, {0, 0, 0}), {});
  EXPECT_EQ(res.status, TrajOptStatus::kBadInput);
}

TEST(TrajOptimizer, RefusesWhenLimitsCannotBeMet) {
  // Starting at 8 m/s toward a wall 1 m away cannot stay in the corridor at 6 m/s^2.
  TrajOptConfig cfg;
  cfg.max_retries = 1;
  cfg.lbfgs.max_iterations = 100;
  TrajOptimizer opt(cfg);
  const auto corridor = boxCorridor();
  const auto res = opt.optimize(pva({5, 0, 1}, {0, -8.0, 0}, {0, 0, 0}),
                                pva({5, 5, 1}, {0, 0, 0}, {0, 0, 0}), {corridor[1]});
  EXPECT_EQ(res.status, TrajOptStatus::kInfeasible) << res.message;
  EXPECT_TRUE(res.trajectory.empty());
  EXPECT_FALSE(res.feasibility.ok);
}

TEST(Lbfgs, MinimisesRosenbrock) {
  CostFunction f = [](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
    g.resize(2);
    const double a = 1 - x(0), b = x(1) - x(0) * x(0);
    g(0) = -2 * a - 400 * x(0) * b;
    g(1) = 200 * b;
    return a * a + 100 * b * b;
  };
  Eigen::VectorXd x(2);
  x << -1.2, 1.0;
  LbfgsConfig cfg;
  cfg.rel_cost_tol = 0.0;
  cfg.g_tol = 1e-9;
  const auto r = lbfgsMinimize(f, x, cfg);
  EXPECT_LT((x - Eigen::Vector2d(1, 1)).norm(), 1e-5) << toString(r.status);
}

TEST(Config, ValidateNamesTheKey) {
  TrajOptConfig cfg;
  cfg.v_max_mps = -1;
  try {
    cfg.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("traj_opt.v_max_mps"), std::string::npos);
  }
  LbfgsConfig l;
  l.memory = 0;
  EXPECT_THROW(l.validate(), ConfigError);
}

}  // namespace
}  // namespace efs::traj

namespace efs::traj {
namespace {

// Random pillar fields around random zig-zag seeds: every optimised trajectory must pass the
// final check (inside the corridor, v <= 1.02 v_max, |a| <= a_max), re-verified here densely.
TEST(TrajOptimizer, RandomCorridorsAllFeasibleAndChecked) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> turn(-1.0, 1.0), seg(2.0, 4.0), u(-1.0, 1.0);
  CorridorConfig ccfg;
  ccfg.max_seed_length_m = 100.0;
  ccfg.clearance_m = 0.3;  // obstacles come to 0.5 m of the seed: corridors 0.2 m wide or less
  CorridorBuilder builder(ccfg);
  TrajOptConfig cfg;
  TrajOptimizer opt(cfg);
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<Eigen::Vector3d> path = {{0, 0, 1.5}};
    double heading = 0;
    for (int k = 0; k < 4 + trial; ++k) {
      heading += turn(rng);
      const double L = seg(rng);
      path.push_back(path.back() +
                     Eigen::Vector3d(L * std::cos(heading), L * std::sin(heading), 0.2 * u(rng)));
    }
    std::vector<Eigen::Vector3d> obstacles;
    for (int i = 0; i < 4000; ++i) {
      const Eigen::Vector3d p =
          path[i % path.size()] + Eigen::Vector3d(3 * u(rng), 3 * u(rng), 1.5 * u(rng));
      double d = 1e9;
      for (size_t k = 0; k + 1 < path.size(); ++k) {
        const Eigen::Vector3d a = path[k], b = path[k + 1];
        const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        d = std::min(d, (a + t * (b - a) - p).norm());
      }
      if (d > 0.5) obstacles.push_back(p);
    }
    const auto corr =
        builder.build(path, obstacles, Eigen::Vector3d(-50, -50, -5), Eigen::Vector3d(50, 50, 5));
    ASSERT_TRUE(corr.ok());
    Eigen::Matrix3d head = Eigen::Matrix3d::Zero(), tail = Eigen::Matrix3d::Zero();
    head.col(0) = path.front();
    // Already moving along the first segment (a sideways start velocity in a 0.2 m wide corridor
    // can be genuinely infeasible at a_max, and is then refused, see RefusesWhenLimitsCannotBeMet).
    head.col(1) = 1.5 * (path[1] - path[0]).normalized();
    tail.col(0) = path.back();
    const auto res = opt.optimize(head, tail, corr.polytopes);
    ASSERT_TRUE(res.ok()) << "trial " << trial << ": " << res.message;
    const Trajectory& tr = res.trajectory;
    for (double t = 0; t <= tr.duration(); t += 0.003) {
      const Eigen::Vector3d p = tr.position(t);
      double best = 1e9;
      for (const auto& poly : corr.polytopes) best = std::min(best, poly.violation(p));
      EXPECT_LE(best, cfg.corridor_tolerance_m) << "trial " << trial << " t " << t;
      EXPECT_LE(tr.velocity(t).norm(), cfg.v_max_mps * 1.02);
      EXPECT_LE(tr.acceleration(t).norm(), cfg.a_max_mps2 + 1e-9);
      for (const auto& o : obstacles) ASSERT_GT((o - p).norm(), 0.2);
    }
  }
}

}  // namespace
}  // namespace efs::traj
