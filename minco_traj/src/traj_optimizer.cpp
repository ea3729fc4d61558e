// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/traj_optimizer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "efs_common/config_check.h"

namespace efs::traj {

void TrajOptConfig::validate() const {
  requireInRange("traj_opt.v_max_mps", v_max_mps, 0.1, 30.0);
  requireInRange("traj_opt.a_max_mps2", a_max_mps2, 0.1, 50.0);
  requireInRange("traj_opt.weight_time", weight_time, 1e-6, 1e8);
  requirePositive("traj_opt.weight_corridor", weight_corridor);
  requirePositive("traj_opt.weight_velocity", weight_velocity);
  requirePositive("traj_opt.weight_acceleration", weight_acceleration);
  requireInRange("traj_opt.smoothing_eps", smoothing_eps, 1e-8, 1.0);
  requireInRange("traj_opt.penalty_velocity_fraction", penalty_velocity_fraction, 0.5, 1.0);
  requireInRange("traj_opt.penalty_acceleration_fraction", penalty_acceleration_fraction, 0.5, 1.0);
  requireInRange("traj_opt.corridor_margin_m", corridor_margin_m, 0.0, 1.0);
  requireInRange("traj_opt.samples_per_piece", samples_per_piece, 2, 1000);
  requireInRange("traj_opt.max_piece_length_m", max_piece_length_m, 0.1, 100.0);
  requireInRange("traj_opt.initial_speed_fraction", initial_speed_fraction, 0.05, 1.0);
  requireInRange("traj_opt.max_retries", max_retries, 0, 10);
  requireInRange("traj_opt.check_dt_s", check_dt_s, 1e-4, 0.5);
  requireInRange("traj_opt.velocity_tolerance", velocity_tolerance, 0.0, 0.5);
  requireInRange("traj_opt.acceleration_tolerance", acceleration_tolerance, 0.0, 0.5);
  requireInRange("traj_opt.corridor_tolerance_m", corridor_tolerance_m, 0.0, 0.5);
  lbfgs.validate();
}

const char* toString(TrajOptStatus s) {
  switch (s) {
    case TrajOptStatus::kOk:
      return "ok";
    case TrajOptStatus::kBadInput:
      return "bad_input";
    case TrajOptStatus::kOptimizerFailed:
      return "optimizer_failed";
    case TrajOptStatus::kInfeasible:
      return "infeasible";
  }
  return "?";
}

namespace {
// Smoothed L1: 0 below 0, cubic knee of width eps, then linear with slope 1.
inline double smoothL1(double x, double eps, double* grad) {
  if (x <= 0.0) {
    *grad = 0.0;
    return 0.0;
  }
  if (x < eps) {
    const double x2 = x * x, e3 = eps * eps * eps;
    *grad = (3.0 * eps * x2 - 2.0 * x2 * x) / e3;
    return (eps - 0.5 * x) * x2 * x / e3;
  }
  *grad = 1.0;
  return x - 0.5 * eps;
}
}  // namespace

MincoCorridorCost::MincoCorridorCost(const TrajOptConfig& cfg, const Eigen::Matrix3d& head,
                                     const Eigen::Matrix3d& tail,
                                     const std::vector<Polytope>& corridor,
                                     const std::vector<int>& piece_polytope)
    : cfg_(cfg),
      corridor_(corridor),
      piece_polytope_(piece_polytope),
      n_(static_cast<int>(piece_polytope.size())) {
  minco_.setConditions(head, tail, n_);
  // Normals as separate x / y / z arrays (vectorised violation test) and margin-shifted offsets.
  for (const auto& poly : corridor_) {
    normals_t_.push_back(poly.A.transpose());
    planes_.push_back({poly.A.col(0).array(), poly.A.col(1).array(), poly.A.col(2).array(),
                       poly.b.array() - cfg_.corridor_margin_m});
  }
}

Eigen::VectorXd MincoCorridorCost::pack(const Eigen::Matrix3Xd& q, const Eigen::VectorXd& T) const {
  Eigen::VectorXd x(dimension());
  x.head(3 * (n_ - 1)) = Eigen::Map<const Eigen::VectorXd>(q.data(), 3 * (n_ - 1));
  x.tail(n_) = T.array().log().matrix();
  return x;
}

void MincoCorridorCost::unpack(const Eigen::VectorXd& x, Eigen::Matrix3Xd* q,
                               Eigen::VectorXd* T) const {
  *q = Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, n_ - 1);
  *T = x.tail(n_).array().exp().matrix();
}

double MincoCorridorCost::operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
  unpack(x, &q_, &T_);
  if (!T_.allFinite() || T_.minCoeff() <= 1e-6 || T_.maxCoeff() > 1e4) {
    grad.setZero(x.size());
    return std::numeric_limits<double>::infinity();
  }
  minco_.setParameters(q_, T_);
  gc_.setZero(6 * n_, 3);
  gT_.setZero(n_);
  double cost = minco_.energy();
  minco_.addEnergyGrad(gc_, gT_);
  cost += cfg_.weight_time * T_.sum();
  gT_.array() += cfg_.weight_time;

  const Eigen::MatrixXd& c = minco_.coeffs();
  const int K = cfg_.samples_per_piece * sample_factor_;
  const double vpen = cfg_.penalty_velocity_fraction * cfg_.v_max_mps;
  const double apen = cfg_.penalty_acceleration_fraction * cfg_.a_max_mps2;
  const double vpen2 = vpen * vpen, apen2 = apen * apen, eps = cfg_.smoothing_eps;
  const double wc = cfg_.weight_corridor * penalty_scale_,
               wv = cfg_.weight_velocity * penalty_scale_,
               wa = cfg_.weight_acceleration * penalty_scale_;
  double b0[6], b1[6], b2[6], b3[6];
  for (int i = 0; i < n_; ++i) {
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& At = normals_t_[piece_polytope_[i]];
    const PlaneArrays& pa = planes_[piece_polytope_[i]];
    const int planes = static_cast<int>(pa.b.size());
    const Eigen::Matrix<double, 6, 3> ci = c.middleRows<6>(6 * i);
    const double T = T_(i);
    for (int j = 0; j <= K; ++j) {
      const double s = double(j) / K, t = s * T;
      const double omega = (j == 0 || j == K) ? 0.5 : 1.0;
      const double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
      b0[0] = 1;
      b0[1] = t;
      b0[2] = t2;
      b0[3] = t3;
      b0[4] = t4;
      b0[5] = t5;
      b1[0] = 0;
      b1[1] = 1;
      b1[2] = 2 * t;
      b1[3] = 3 * t2;
      b1[4] = 4 * t3;
      b1[5] = 5 * t4;
      b2[0] = 0;
      b2[1] = 0;
      b2[2] = 2;
      b2[3] = 6 * t;
      b2[4] = 12 * t2;
      b2[5] = 20 * t3;
      b3[0] = 0;
      b3[1] = 0;
      b3[2] = 0;
      b3[3] = 6;
      b3[4] = 24 * t;
      b3[5] = 60 * t2;
      const Eigen::Vector3d p = ci.transpose() * Eigen::Map<const Eigen::Matrix<double, 6, 1>>(b0);
      const Eigen::Vector3d v = ci.transpose() * Eigen::Map<const Eigen::Matrix<double, 6, 1>>(b1);
      const Eigen::Vector3d a = ci.transpose() * Eigen::Map<const Eigen::Matrix<double, 6, 1>>(b2);
      const Eigen::Vector3d jk = ci.transpose() * Eigen::Map<const Eigen::Matrix<double, 6, 1>>(b3);
      Eigen::Vector3d gp = Eigen::Vector3d::Zero(), gv = gp, ga = gp;
      double pen = 0.0, dphi;
      viol_.resize(planes);
      viol_ = pa.nx * p.x() + pa.ny * p.y() + pa.nz * p.z() - pa.b;
      if (viol_.maxCoeff() > 0.0) {
        for (int h = 0; h < planes; ++h) {
          if (viol_(h) <= 0.0) continue;
          pen += wc * smoothL1(viol_(h), eps, &dphi);
          gp += wc * dphi * At.col(h);
        }
      }
      const double vv = v.squaredNorm() - vpen2;
      if (vv > 0.0) {
        pen += wv * smoothL1(vv, eps, &dphi);
        gv += wv * dphi * 2.0 * v;
      }
      const double aa = a.squaredNorm() - apen2;
      if (aa > 0.0) {
        pen += wa * smoothL1(aa, eps, &dphi);
        ga += wa * dphi * 2.0 * a;
      }
      if (pen == 0.0) continue;
      const double w = omega * T / K;
      cost += w * pen;
      for (int k = 0; k < 6; ++k)
        gc_.row(6 * i + k) += w * (b0[k] * gp + b1[k] * gv + b2[k] * ga).transpose();
      // Explicit T dependence: the quadrature weight and the sample time t = s T.
      gT_(i) += omega / K * pen + w * s * (gp.dot(v) + gv.dot(a) + ga.dot(jk));
    }
  }
  minco_.propagateGrad(gc_, gT_, gq_, gT_total_);
  grad.resize(x.size());
  grad.head(3 * (n_ - 1)) = Eigen::Map<const Eigen::VectorXd>(gq_.data(), 3 * (n_ - 1));
  grad.tail(n_) = (gT_total_.array() * T_.array()).matrix();
  return cost;
}

TrajOptimizer::TrajOptimizer(const TrajOptConfig& cfg) : cfg_(cfg) { cfg_.validate(); }

FeasibilityReport TrajOptimizer::check(const Trajectory& traj,
                                       const std::vector<Polytope>& corridor) const {
  FeasibilityReport rep;
  if (traj.empty()) {
    rep.reason = "empty trajectory";
    return rep;
  }
  // A plan cannot undo its initial state at once: limits start from what the head already has
  // (a reference braking at a_max hands its full acceleration to the next plan).
  const TrajectoryPoint head = traj.sample(0.0);
  const double v_limit =
      std::max(cfg_.v_max_mps, head.v_world_mps.norm()) * (1.0 + cfg_.velocity_tolerance);
  const double a_limit =
      std::max(cfg_.a_max_mps2, head.a_world_mps2.norm()) * (1.0 + cfg_.acceleration_tolerance);
  const double dur = traj.duration();
  const int steps = std::max(1, static_cast<int>(std::ceil(dur / cfg_.check_dt_s)));
  std::ostringstream why;
  for (int k = 0; k <= steps; ++k) {
    const double t = dur * k / steps;
    const Eigen::Vector3d p = traj.position(t);
    const double sp = traj.velocity(t).norm(), ac = traj.acceleration(t).norm();
    rep.max_speed_mps = std::max(rep.max_speed_mps, sp);
    rep.max_acceleration_mps2 = std::max(rep.max_acceleration_mps2, ac);
    double best = 1e300;  // smallest violation over polytopes: <= 0 means inside one of them
    for (const auto& poly : corridor) best = std::min(best, poly.violation(p));
    rep.max_corridor_violation_m = std::max(rep.max_corridor_violation_m, best);
  }
  rep.ok = true;
  if (!(rep.max_speed_mps <= v_limit)) {
    rep.ok = false;
    why << "speed " << rep.max_speed_mps << " m/s > limit; ";
  }
  if (!(rep.max_acceleration_mps2 <= a_limit)) {
    rep.ok = false;
    why << "acceleration " << rep.max_acceleration_mps2 << " m/s^2 > limit; ";
  }
  if (!(rep.max_corridor_violation_m <= cfg_.corridor_tolerance_m)) {
    rep.ok = false;
    why << "leaves the corridor by " << rep.max_corridor_violation_m << " m; ";
  }
  rep.reason = why.str();
  return rep;
}

namespace {
// Rest-to-rest time over distance L with a speed cap and an acceleration (trapezoid profile).
double restToRestTime(double L, double v, double a) {
  if (L <= v * v / a) return 2.0 * std::sqrt(L / a);
  return L / v + v / a;
}
}  // namespace

TrajOptResult TrajOptimizer::optimize(const Eigen::Matrix3d& head, const Eigen::Matrix3d& tail,
                                      const std::vector<Polytope>& corridor) const {
  TrajOptResult res;
  if (corridor.empty() || !head.allFinite() || !tail.allFinite()) {
    res.message = corridor.empty() ? "empty corridor" : "non-finite boundary conditions";
    return res;
  }
  if (!corridor.front().contains(head.col(0), cfg_.corridor_tolerance_m) ||
      !corridor.back().contains(tail.col(0), cfg_.corridor_tolerance_m)) {
    res.message = "start or goal outside the first/last polytope";
    return res;
  }
  // Pieces and the initial joints along the seeds.
  std::vector<Eigen::Vector3d> joints;
  std::vector<int>& pp = res.piece_polytope;
  for (size_t k = 0; k < corridor.size(); ++k) {
    const auto& poly = corridor[k];
    const Eigen::Vector3d a = k == 0 ? Eigen::Vector3d(head.col(0)) : poly.seed_start_m;
    const Eigen::Vector3d b =
        k + 1 == corridor.size() ? Eigen::Vector3d(tail.col(0)) : poly.seed_end_m;
    const int m =
        std::max(1, static_cast<int>(std::ceil((b - a).norm() / cfg_.max_piece_length_m)));
    for (int j = 0; j < m; ++j) {
      pp.push_back(static_cast<int>(k));
      if (!(k + 1 == corridor.size() && j + 1 == m))
        joints.push_back(a + (b - a) * double(j + 1) / m);
    }
  }
  const int n = static_cast<int>(pp.size());
  Eigen::Matrix3Xd q(3, n - 1);
  Eigen::VectorXd T(n);
  const double v0 = cfg_.initial_speed_fraction * cfg_.v_max_mps;
  const double a0 = 0.5 * cfg_.a_max_mps2;
  std::vector<Eigen::Vector3d> pts;
  pts.push_back(head.col(0));
  for (const auto& j : joints) pts.push_back(j);
  pts.push_back(tail.col(0));
  double total_len = 0.0;
  for (int i = 0; i < n; ++i) total_len += (pts[i + 1] - pts[i]).norm();
  const double total_T = std::max(0.5, restToRestTime(total_len, v0, a0));
  for (int i = 0; i < n; ++i) {
    if (i < n - 1) q.col(i) = pts[i + 1];
    const double L = (pts[i + 1] - pts[i]).norm();
    T(i) = std::max(0.2, total_len > 1e-9 ? total_T * L / total_len : total_T / n);
  }
  MincoCorridorCost cost(cfg_, head, tail, corridor, pp);
  Eigen::VectorXd x = cost.pack(q, T);
  CostFunction f = [&cost](const Eigen::VectorXd& xx, Eigen::VectorXd& g) { return cost(xx, g); };
  double scale = 1.0;
  for (int attempt = 0; attempt <= cfg_.max_retries; ++attempt) {
    cost.setPenaltyScale(scale);
    cost.setSampleFactor(1 << attempt);  // retries also sample the penalties more densely
    res.retries = attempt;
    try {
      // Residual violations are a tiny part of the cost, so retries also ask for more progress.
      LbfgsConfig lb = cfg_.lbfgs;
      lb.rel_cost_tol *= std::pow(0.01, attempt);
      res.solver = lbfgsMinimize(f, x, lb);
    } catch (const std::exception& e) {
      res.status = TrajOptStatus::kOptimizerFailed;
      res.message = e.what();
      return res;
    }
    if (res.solver.status == LbfgsStatus::kNonFinite) {
      res.status = TrajOptStatus::kOptimizerFailed;
      res.message = "non-finite cost";
      return res;
    }
    cost.unpack(x, &q, &T);
    cost.minco().setParameters(q, T);
    res.trajectory = cost.minco().toTrajectory();
    res.feasibility = check(res.trajectory, corridor);
    if (res.feasibility.ok) {
      res.status = TrajOptStatus::kOk;
      res.message.clear();
      return res;
    }
    scale *= 10.0;
  }
  res.status = TrajOptStatus::kInfeasible;
  res.message = "final check failed: " + res.feasibility.reason;
  res.trajectory = Trajectory();  // an unchecked trajectory is never handed out
  return res;
}

}  // namespace efs::traj
