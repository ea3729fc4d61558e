// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Dense asymmetric cost matrix shared by the ATSP solver, the MCTS sequencer and the FE-TSP.
// "No edge" is +infinity under the name kUnreachable, never a finite "large number": the solvers
// replace it internally by a bound that no finite tour can reach and report whether the answer
// had to use one.
#pragma once

#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace efs::planner {

inline constexpr double kUnreachable = std::numeric_limits<double>::infinity();

class CostMatrix {
 public:
  CostMatrix() = default;
  explicit CostMatrix(int n, double fill = 0.0)
      : n_(n), d_(static_cast<size_t>(n < 0 ? 0 : n) * (n < 0 ? 0 : n), fill) {
    if (n < 0) throw std::invalid_argument("CostMatrix: negative size " + std::to_string(n));
  }

  int size() const { return n_; }
  double operator()(int i, int j) const { return d_[static_cast<size_t>(i) * n_ + j]; }
  double& operator()(int i, int j) { return d_[static_cast<size_t>(i) * n_ + j]; }
  const double* data() const { return d_.data(); }
  bool reachable(int i, int j) const { return (*this)(i, j) < kUnreachable; }

 private:
  int n_ = 0;
  std::vector<double> d_;
};

/// Cost of visiting `order` in sequence; closes the cycle back to order[0] when `closed`.
inline double pathCost(const CostMatrix& c, const std::vector<int>& order, bool closed) {
  double sum = 0.0;
  for (size_t k = 0; k + 1 < order.size(); ++k) sum += c(order[k], order[k + 1]);
  if (closed && order.size() > 1) sum += c(order.back(), order.front());
  return sum;
}

}  // namespace efs::planner
