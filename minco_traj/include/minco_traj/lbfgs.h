// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// A small limited-memory BFGS minimiser (Nocedal & Wright, Alg. 7.4 two-loop recursion) with a
// Lewis-Overton bisection line search for the weak Wolfe conditions, which is robust on the
// piecewise-smooth penalty costs of trajectory optimisation. Own implementation; no allocation
// per iteration beyond the first.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>

namespace efs::traj {

struct LbfgsConfig {
  int memory = 8;
  int max_iterations = 200;
  int max_line_search_steps = 40;
  double armijo_c1 = 1e-4;
  double wolfe_c2 = 0.9;
  /// Stop when |g|_inf <= g_tol * max(1, |x|_inf).
  double g_tol = 1e-6;
  /// Stop when the cost decreased by less than this fraction over `past` iterations.
  double rel_cost_tol = 1e-4;
  int past = 3;
  void validate() const;
};

enum class LbfgsStatus { kConverged, kStalled, kMaxIterations, kLineSearchFailed, kNonFinite };
const char* toString(LbfgsStatus s);

struct LbfgsResult {
  LbfgsStatus status = LbfgsStatus::kMaxIterations;
  double cost = 0.0;
  int iterations = 0;
  int evaluations = 0;
};

/// f(x, grad) returns the cost and writes the gradient.
using CostFunction = std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd& grad)>;

/// Minimises f starting from x (overwritten with the best point found).
LbfgsResult lbfgsMinimize(const CostFunction& f, Eigen::VectorXd& x, const LbfgsConfig& cfg);

}  // namespace efs::traj
