// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/lbfgs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "efs_common/config_check.h"

namespace efs::traj {

void LbfgsConfig::validate() const {
  requireInRange("lbfgs.memory", memory, 1, 64);
  requireInRange("lbfgs.max_iterations", max_iterations, 1, 100000);
  requireInRange("lbfgs.max_line_search_steps", max_line_search_steps, 1, 200);
  requireInRange("lbfgs.armijo_c1", armijo_c1, 1e-12, 0.5);
  requireInRange("lbfgs.wolfe_c2", wolfe_c2, armijo_c1, 1.0 - 1e-9);
  requireInRange("lbfgs.g_tol", g_tol, 0.0, 1.0);
  requireInRange("lbfgs.rel_cost_tol", rel_cost_tol, 0.0, 1.0);
  requireInRange("lbfgs.past", past, 1, 1000);
}

const char* toString(LbfgsStatus s) {
  switch (s) {
    case LbfgsStatus::kConverged:
      return "converged";
    case LbfgsStatus::kStalled:
      return "stalled";
    case LbfgsStatus::kMaxIterations:
      return "max_iterations";
    case LbfgsStatus::kLineSearchFailed:
      return "line_search_failed";
    case LbfgsStatus::kNonFinite:
      return "non_finite";
  }
  return "unknown";
}

LbfgsResult lbfgsMinimize(const CostFunction& f, Eigen::VectorXd& x, const LbfgsConfig& cfg) {
  const int n = static_cast<int>(x.size());
  const int m = cfg.memory;
  LbfgsResult res;
  Eigen::VectorXd g(n), d(n), x_new(n), g_new(n);
  Eigen::MatrixXd S(n, m), Y(n, m);
  std::vector<double> rho(m), alpha(m);
  std::vector<double> history;
  int stored = 0, head = 0;

  double fx = f(x, g);
  res.evaluations = 1;
  if (!std::isfinite(fx) || !g.allFinite()) {
    res.status = LbfgsStatus::kNonFinite;
    res.cost = fx;
    return res;
  }
  history.push_back(fx);
  d = -g;
  double step = 1.0 / std::max(1.0, g.norm());
  for (int it = 0; it < cfg.max_iterations; ++it) {
    res.iterations = it + 1;
    if (g.lpNorm<Eigen::Infinity>() <= cfg.g_tol * std::max(1.0, x.lpNorm<Eigen::Infinity>())) {
      res.status = LbfgsStatus::kConverged;
      break;
    }
    double dg0 = g.dot(d);
    if (!(dg0 < 0.0)) {  // not a descent direction: restart with steepest descent
      stored = 0;
      d = -g;
      dg0 = g.dot(d);
      step = 1.0 / std::max(1.0, g.norm());
    }
    // Lewis-Overton bisection for the weak Wolfe conditions.
    double lo = 0.0, hi = std::numeric_limits<double>::infinity();
    double fn = fx;
    bool ok = false;
    for (int ls = 0; ls < cfg.max_line_search_steps; ++ls) {
      x_new = x + step * d;
      fn = f(x_new, g_new);
      ++res.evaluations;
      if (!std::isfinite(fn) || !g_new.allFinite() || fn > fx + cfg.armijo_c1 * step * dg0) {
        hi = step;
      } else if (g_new.dot(d) < cfg.wolfe_c2 * dg0) {
        lo = step;
      } else {
        ok = true;
        break;
      }
      step = std::isinf(hi) ? 2.0 * step : 0.5 * (lo + hi);
    }
    if (!ok) {
      // Accept a merely decreasing point if the search found one; otherwise give up.
      if (lo > 0.0) {
        x_new = x + lo * d;
        fn = f(x_new, g_new);
        ++res.evaluations;
      }
      if (!(lo > 0.0) || !(fn < fx)) {
        res.status = LbfgsStatus::kLineSearchFailed;
        break;
      }
    }
    const Eigen::VectorXd s = x_new - x, y = g_new - g;
    x = x_new;
    g = g_new;
    fx = fn;
    history.push_back(fx);
    const int hs = static_cast<int>(history.size());
    if (hs > cfg.past) {
      const double prev = history[hs - 1 - cfg.past];
      if ((prev - fx) <= cfg.rel_cost_tol * std::max(1.0, std::abs(fx))) {
        res.status = LbfgsStatus::kStalled;
        break;
      }
    }
    const double sy = s.dot(y);
    if (sy > 1e-12 * std::max(1e-300, y.squaredNorm())) {  // keep the update positive definite
      S.col(head) = s;
      Y.col(head) = y;
      rho[head] = 1.0 / sy;
      head = (head + 1) % m;
      stored = std::min(stored + 1, m);
    }
    // Two-loop recursion.
    d = -g;
    for (int k = 0; k < stored; ++k) {
      const int idx = (head - 1 - k + m) % m;
      alpha[idx] = rho[idx] * S.col(idx).dot(d);
      d -= alpha[idx] * Y.col(idx);
    }
    if (stored > 0) {
      const int last = (head - 1 + m) % m;
      d *= 1.0 / (rho[last] * Y.col(last).squaredNorm());
    }
    for (int k = stored - 1; k >= 0; --k) {
      const int idx = (head - 1 - k + m) % m;
      const double beta = rho[idx] * Y.col(idx).dot(d);
      d += S.col(idx) * (alpha[idx] - beta);
    }
    step = 1.0;
  }
  res.cost = fx;
  return res;
}

}  // namespace efs::traj
