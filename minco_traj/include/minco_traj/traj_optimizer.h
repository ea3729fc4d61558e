// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Spatio-temporal MINCO optimisation in a safe flight corridor (paper Sec. VI-E). Decision
// variables: the intermediate points q (free, one per joint) and tau with T = exp(tau) (the
// diffeomorphic time map keeps durations positive without constraints). Cost:
//   int |jerk|^2 dt + weight_time * sum T
//   + sampled, time-weighted smooth penalties (smoothed L1, GCOPTER-style) on
//     corridor half-spaces of each piece's polytope, |v|^2 <= v_pen^2 and |a|^2 <= a_pen^2,
// minimised by our L-BFGS. Penalties bind slightly inside the limits (penalty_*_fraction) so that
// the final feasibility check, which samples the result densely (inside the union of the
// corridor's polytopes, |v| <= v_max * (1 + velocity_tolerance), |a| <= a_max), passes. A result
// that fails the check is retried from where it stopped with 10x penalty weights, twice the
// samples per piece and a 100x tighter stopping tolerance (max_retries times), then refused
// (never returned).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "minco_traj/corridor.h"
#include "minco_traj/lbfgs.h"
#include "minco_traj/minco.h"
#include "minco_traj/trajectory.h"

namespace efs::traj {

struct TrajOptConfig {
  double v_max_mps = 4.0;
  double a_max_mps2 = 6.0;
  double weight_time = 512.0;
  double weight_corridor = 1e5;
  double weight_velocity = 1e4;
  double weight_acceleration = 1e4;
  double smoothing_eps = 1e-2;  ///< width of the smoothed-L1 knee
  double penalty_velocity_fraction = 0.97;
  double penalty_acceleration_fraction = 0.95;
  double corridor_margin_m = 0.05;  ///< penalties keep samples this far inside
  int samples_per_piece = 12;
  double max_piece_length_m = 3.0;  ///< long seeds get several pieces in their polytope
  double initial_speed_fraction = 0.6;
  int max_retries = 2;
  // Feasibility check of the result.
  double check_dt_s = 0.01;
  /// v <= max(v_max, |v(0)|) * (1 + this): a plan may start faster than the limit, not speed up
  double velocity_tolerance = 0.02;
  /// a <= max(a_max, |a(0)|) * (1 + this): e.g. plans that start from an emergency brake at a_max
  double acceleration_tolerance = 0.02;
  double corridor_tolerance_m = 1e-3;
  LbfgsConfig lbfgs;
  void validate() const;
};

enum class TrajOptStatus { kOk, kBadInput, kOptimizerFailed, kInfeasible };
const char* toString(TrajOptStatus s);

struct FeasibilityReport {
  bool ok = false;
  double max_speed_mps = 0.0;
  double max_acceleration_mps2 = 0.0;
  double max_corridor_violation_m = 0.0;  ///< distance outside the union of polytopes (approx.)
  std::string reason;
};

struct TrajOptResult {
  TrajOptStatus status = TrajOptStatus::kBadInput;
  Trajectory trajectory;
  FeasibilityReport feasibility;
  LbfgsResult solver;
  int retries = 0;
  std::vector<int> piece_polytope;  ///< which polytope each piece is constrained to
  std::string message;
  bool ok() const { return status == TrajOptStatus::kOk; }
};

/// The cost of the problem for fixed conditions, exposed for gradient tests and benchmarks.
class MincoCorridorCost {
 public:
  MincoCorridorCost(const TrajOptConfig& cfg, const Eigen::Matrix3d& head_pva,
                    const Eigen::Matrix3d& tail_pva, const std::vector<Polytope>& corridor,
                    const std::vector<int>& piece_polytope);
  int pieceCount() const { return n_; }
  int dimension() const { return 3 * (n_ - 1) + n_; }
  /// x = [q (3 x N-1, column-major); tau (N)].
  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad);
  void setPenaltyScale(double s) { penalty_scale_ = s; }
  void setSampleFactor(int f) { sample_factor_ = f; }
  Eigen::VectorXd pack(const Eigen::Matrix3Xd& q, const Eigen::VectorXd& T) const;
  void unpack(const Eigen::VectorXd& x, Eigen::Matrix3Xd* q, Eigen::VectorXd* T) const;
  MincoS3& minco() { return minco_; }

 private:
  TrajOptConfig cfg_;
  const std::vector<Polytope>& corridor_;
  std::vector<int> piece_polytope_;
  std::vector<Eigen::Matrix<double, 3, Eigen::Dynamic>> normals_t_;
  struct PlaneArrays {
    Eigen::ArrayXd nx, ny, nz, b;
  };
  std::vector<PlaneArrays> planes_;
  Eigen::ArrayXd viol_;
  int n_;
  MincoS3 minco_;
  double penalty_scale_ = 1.0;
  int sample_factor_ = 1;
  Eigen::MatrixXd gc_;
  Eigen::VectorXd gT_, gT_total_;
  Eigen::Matrix3Xd q_, gq_;
  Eigen::VectorXd T_;
};

class TrajOptimizer {
 public:
  explicit TrajOptimizer(const TrajOptConfig& cfg = {});
  const TrajOptConfig& config() const { return cfg_; }

  /// head/tail: columns p, v, a. The head position must lie in the first polytope and the tail
  /// position in the last; consecutive polytopes must overlap (as CorridorBuilder makes them).
  TrajOptResult optimize(const Eigen::Matrix3d& head_pva, const Eigen::Matrix3d& tail_pva,
                         const std::vector<Polytope>& corridor) const;

  /// Dense check of a trajectory against a corridor and the dynamic limits.
  FeasibilityReport check(const Trajectory& traj, const std::vector<Polytope>& corridor) const;

 private:
  TrajOptConfig cfg_;
};

}  // namespace efs::traj
