// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// MINCO for s = 3 (minimum jerk, piecewise quintic): the map from intermediate points q and piece
// durations T to the unique jerk-optimal coefficients c = M(T)^{-1} b(q), and the adjoint that
// turns any gradient dK/dc into dK/dq and dK/dT (Wang et al., "Geometrically constrained
// trajectory optimization for multicopters", T-RO 2022). Written from the paper's idea:
//   * unknowns: 6 coefficients per piece and axis, column k multiplying t^k;
//   * equations: head p,v,a; per joint jerk and snap continuity, the position pinned to q_i,
//     position, velocity and acceleration continuity; tail p,v,a. Ordered this way M is banded
//     with 6 sub- and 6 super-diagonals and factors without pivoting;
//   * adjoint: G = M^{-T} dK/dc; dK/dq_i is G's row of the pinned-position equation and
//     dK/dT_i = -sum_rows G_r . (dM_r/dT_i) c_i, where d/dT of a row beta^(k)(T) is beta^(k+1)(T).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "minco_traj/trajectory.h"

namespace efs::traj {

/// Square banded matrix with equal lower/upper bandwidth, LU without pivoting.
class BandedSystem {
 public:
  void create(int n, int bandwidth);
  int size() const { return n_; }
  double& operator()(int i, int j) { return data_[static_cast<size_t>(i) * w2_ + (j - i + bw_)]; }
  double operator()(int i, int j) const {
    return data_[static_cast<size_t>(i) * w2_ + (j - i + bw_)];
  }
  void setZero();
  /// In-place LU; throws std::runtime_error on a (near) zero pivot.
  void factorize();
  /// Solves M x = b in place (after factorize), b is n x k.
  void solve(Eigen::MatrixXd& b) const;
  /// Solves M^T x = b in place (after factorize).
  void solveTranspose(Eigen::MatrixXd& b) const;

 private:
  int n_ = 0, bw_ = 0, w2_ = 0;
  std::vector<double> data_;
};

class MincoS3 {
 public:
  /// head/tail: columns p, v, a (world frame).
  void setConditions(const Eigen::Matrix3d& head_pva, const Eigen::Matrix3d& tail_pva,
                     int piece_count);
  /// q: 3 x (N-1) intermediate points; T: N durations (> 0). Solves for the coefficients.
  void setParameters(const Eigen::Matrix3Xd& q, const Eigen::VectorXd& T);

  int pieceCount() const { return n_; }
  /// 6N x 3; row 6i+k is the t^k coefficient of piece i.
  const Eigen::MatrixXd& coeffs() const { return c_; }
  const Eigen::VectorXd& durations() const { return T_; }

  /// Control effort sum_i int_0^{T_i} |jerk|^2 dt.
  double energy() const;
  /// Adds d(energy)/dc to gc (6N x 3) and the explicit d(energy)/dT to gT.
  void addEnergyGrad(Eigen::MatrixXd& gc, Eigen::VectorXd& gT) const;
  /// Given dK/dc (6N x 3) and the explicit dK/dT, returns dK/dq (3 x N-1) and total dK/dT.
  void propagateGrad(const Eigen::MatrixXd& gc, const Eigen::VectorXd& gT_explicit,
                     Eigen::Matrix3Xd& gq, Eigen::VectorXd& gT) const;

  Trajectory toTrajectory() const;
  PieceCoeffs piece(int i) const { return c_.block<6, 3>(6 * i, 0).transpose(); }

 private:
  int n_ = 0;
  Eigen::Matrix3d head_, tail_;
  Eigen::VectorXd T_;
  Eigen::MatrixXd b_, c_;
  BandedSystem A_;
  mutable Eigen::MatrixXd adjoint_;  ///< scratch for propagateGrad (no allocation per call)
};

}  // namespace efs::traj
