// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/minco.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace efs::traj {

void BandedSystem::create(int n, int bandwidth) {
  n_ = n;
  bw_ = bandwidth;
  w2_ = 2 * bandwidth + 1;
  data_.assign(static_cast<size_t>(n) * w2_, 0.0);
}

void BandedSystem::setZero() { std::fill(data_.begin(), data_.end(), 0.0); }

void BandedSystem::factorize() {
  BandedSystem& a = *this;
  for (int k = 0; k < n_; ++k) {
    const double piv = a(k, k);
    if (!(std::abs(piv) > 1e-300)) throw std::runtime_error("BandedSystem: zero pivot");
    const int iend = std::min(n_ - 1, k + bw_);
    const int jend = std::min(n_ - 1, k + bw_);
    for (int i = k + 1; i <= iend; ++i) {
      double& lik = a(i, k);
      if (lik == 0.0) continue;
      lik /= piv;
      for (int j = k + 1; j <= jend; ++j) a(i, j) -= lik * a(k, j);
    }
  }
}

void BandedSystem::solve(Eigen::MatrixXd& b) const {
  const BandedSystem& a = *this;
  for (int i = 0; i < n_; ++i)
    for (int j = std::max(0, i - bw_); j < i; ++j) b.row(i) -= a(i, j) * b.row(j);
  for (int i = n_ - 1; i >= 0; --i) {
    for (int j = i + 1; j <= std::min(n_ - 1, i + bw_); ++j) b.row(i) -= a(i, j) * b.row(j);
    b.row(i) /= a(i, i);
  }
}

void BandedSystem::solveTranspose(Eigen::MatrixXd& b) const {
  const BandedSystem& a = *this;
  // M^T = U^T L^T: U^T is lower triangular, L^T is unit upper triangular.
  for (int i = 0; i < n_; ++i) {
    for (int j = std::max(0, i - bw_); j < i; ++j) b.row(i) -= a(j, i) * b.row(j);
    b.row(i) /= a(i, i);
  }
  for (int i = n_ - 1; i >= 0; --i)
    for (int j = i + 1; j <= std::min(n_ - 1, i + bw_); ++j) b.row(i) -= a(j, i) * b.row(j);
}

namespace {
// Row of d^order/dt^order [1 t t^2 t^3 t^4 t^5] at t.
inline void basis(double t, int order, double out[6]) {
  // Falling factorials k!/(k-order)! for order 0..5.
  static const double kFall[6][6] = {{1, 1, 1, 1, 1, 1},    {0, 1, 2, 3, 4, 5},
                                     {0, 0, 2, 6, 12, 20},  {0, 0, 0, 6, 24, 60},
                                     {0, 0, 0, 0, 24, 120}, {0, 0, 0, 0, 0, 120}};
  double tp = 1.0;
  for (int k = 0; k < 6; ++k) {
    if (k < order) {
      out[k] = 0.0;
      continue;
    }
    out[k] = kFall[order][k] * tp;
    tp *= t;
  }
}
}  // namespace

void MincoS3::setConditions(const Eigen::Matrix3d& head, const Eigen::Matrix3d& tail, int n) {
  if (n < 1) throw std::invalid_argument("MincoS3: piece_count must be >= 1");
  n_ = n;
  head_ = head;
  tail_ = tail;
  A_.create(6 * n, 6);
  b_.setZero(6 * n, 3);
  c_.setZero(6 * n, 3);
  T_.setOnes(n);
}

void MincoS3::setParameters(const Eigen::Matrix3Xd& q, const Eigen::VectorXd& T) {
  if (q.cols() != n_ - 1 || T.size() != n_)
    throw std::invalid_argument("MincoS3::setParameters: q must be 3 x (N-1) and T of size N");
  T_ = T;
  A_.setZero();
  b_.setZero();
  double row[6];
  A_(0, 0) = 1.0;
  A_(1, 1) = 1.0;
  A_(2, 2) = 2.0;
  b_.row(0) = head_.col(0).transpose();
  b_.row(1) = head_.col(1).transpose();
  b_.row(2) = head_.col(2).transpose();
  for (int i = 0; i < n_ - 1; ++i) {
    const int r = 6 * i + 3, c0 = 6 * i, c1 = 6 * (i + 1);
    const double t = T(i);
    basis(t, 3, row);  // jerk continuity
    for (int k = 0; k < 6; ++k) A_(r, c0 + k) = row[k];
    A_(r, c1 + 3) = -6.0;
    basis(t, 4, row);  // snap continuity
    for (int k = 0; k < 6; ++k) A_(r + 1, c0 + k) = row[k];
    A_(r + 1, c1 + 4) = -24.0;
    basis(t, 0, row);  // position pinned to q_i
    for (int k = 0; k < 6; ++k) A_(r + 2, c0 + k) = row[k];
    b_.row(r + 2) = q.col(i).transpose();
    for (int k = 0; k < 6; ++k) A_(r + 3, c0 + k) = row[k];  // position continuity
    A_(r + 3, c1) = -1.0;
    basis(t, 1, row);  // velocity continuity
    for (int k = 0; k < 6; ++k) A_(r + 4, c0 + k) = row[k];
    A_(r + 4, c1 + 1) = -1.0;
    basis(t, 2, row);  // acceleration continuity
    for (int k = 0; k < 6; ++k) A_(r + 5, c0 + k) = row[k];
    A_(r + 5, c1 + 2) = -2.0;
  }
  const int r = 6 * n_ - 3, c0 = 6 * (n_ - 1);
  for (int d = 0; d < 3; ++d) {
    basis(T(n_ - 1), d, row);
    for (int k = 0; k < 6; ++k) A_(r + d, c0 + k) = row[k];
    b_.row(r + d) = tail_.col(d).transpose();
  }
  A_.factorize();
  c_ = b_;
  A_.solve(c_);
}

double MincoS3::energy() const {
  double e = 0.0;
  for (int i = 0; i < n_; ++i) {
    const double t1 = T_(i), t2 = t1 * t1, t3 = t2 * t1, t4 = t3 * t1, t5 = t4 * t1;
    const Eigen::RowVector3d c3 = c_.row(6 * i + 3), c4 = c_.row(6 * i + 4), c5 = c_.row(6 * i + 5);
    e += 36.0 * c3.squaredNorm() * t1 + 144.0 * c3.dot(c4) * t2 +
         (192.0 * c4.squaredNorm() + 240.0 * c3.dot(c5)) * t3 + 720.0 * c4.dot(c5) * t4 +
         720.0 * c5.squaredNorm() * t5;
  }
  return e;
}

void MincoS3::addEnergyGrad(Eigen::MatrixXd& gc, Eigen::VectorXd& gT) const {
  for (int i = 0; i < n_; ++i) {
    const double t1 = T_(i), t2 = t1 * t1, t3 = t2 * t1, t4 = t3 * t1, t5 = t4 * t1;
    const Eigen::RowVector3d c3 = c_.row(6 * i + 3), c4 = c_.row(6 * i + 4), c5 = c_.row(6 * i + 5);
    gc.row(6 * i + 3) += 72.0 * c3 * t1 + 144.0 * c4 * t2 + 240.0 * c5 * t3;
    gc.row(6 * i + 4) += 144.0 * c3 * t2 + 384.0 * c4 * t3 + 720.0 * c5 * t4;
    gc.row(6 * i + 5) += 240.0 * c3 * t3 + 720.0 * c4 * t4 + 1440.0 * c5 * t5;
    // d/dT of the integral is the integrand at T.
    const Eigen::RowVector3d jerk_end = 6.0 * c3 + 24.0 * c4 * t1 + 60.0 * c5 * t2;
    gT(i) += jerk_end.squaredNorm();
  }
}

void MincoS3::propagateGrad(const Eigen::MatrixXd& gc, const Eigen::VectorXd& gT_explicit,
                            Eigen::Matrix3Xd& gq, Eigen::VectorXd& gT) const {
  Eigen::MatrixXd& G = adjoint_;
  G = gc;
  A_.solveTranspose(G);
  gq.resize(3, n_ - 1);
  gT = gT_explicit;
  for (int i = 0; i < n_; ++i) {
    const PieceCoeffs ci = piece(i);
    const double t = T_(i);
    const Eigen::Vector3d v = Trajectory::evalPiece(ci, t, 1), a = Trajectory::evalPiece(ci, t, 2),
                          j = Trajectory::evalPiece(ci, t, 3), s = Trajectory::evalPiece(ci, t, 4),
                          k5 = Trajectory::evalPiece(ci, t, 5);
    double d = 0.0;
    if (i < n_ - 1) {
      const int r = 6 * i + 3;
      gq.col(i) = G.row(r + 2).transpose();
      d += G.row(r).dot(s) + G.row(r + 1).dot(k5) + G.row(r + 2).dot(v) + G.row(r + 3).dot(v) +
           G.row(r + 4).dot(a) + G.row(r + 5).dot(j);
    } else {
      const int r = 6 * n_ - 3;
      d += G.row(r).dot(v) + G.row(r + 1).dot(a) + G.row(r + 2).dot(j);
    }
    gT(i) -= d;
  }
}

Trajectory MincoS3::toTrajectory() const {
  std::vector<PieceCoeffs> pieces;
  std::vector<double> durs;
  for (int i = 0; i < n_; ++i) {
    pieces.push_back(piece(i));
    durs.push_back(T_(i));
  }
  return Trajectory(std::move(pieces), std::move(durs));
}

}  // namespace efs::traj
