// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/corridor.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "efs_common/config_check.h"

namespace efs::traj {

using MatX3 = Eigen::Matrix<double, Eigen::Dynamic, 3>;

double Polytope::violation(const Eigen::Vector3d& p) const {
  if (b.size() == 0) return -1e300;
  return (A * p - b).maxCoeff();
}

void CorridorConfig::validate() const {
  requireInRange("corridor.clearance_m", clearance_m, 0.0, 5.0);
  requireInRange("corridor.box_margin_m", box_margin_m, 0.1, 50.0);
  requireInRange("corridor.max_seed_length_m", max_seed_length_m, 0.1, 100.0);
  requireInRange("corridor.blind_depth_m", blind_depth_m, 0.0, 100.0);
  requireThat(blind_depth_m == 0.0 || blind_depth_m > clearance_m, "corridor.blind_depth_m",
              "must be 0 (off) or more than corridor.clearance_m, else the path itself is blocked");
  requireInRange("corridor.iterations", iterations, 1, 20);
  requireInRange("corridor.initial_radius_m", initial_radius_m, 1e-3, 10.0);
  requireInRange("corridor.mvie_newton_steps", mvie_newton_steps, 0, 200);
}

const char* toString(CorridorStatus s) {
  switch (s) {
    case CorridorStatus::kOk:
      return "ok";
    case CorridorStatus::kEmptyPath:
      return "empty_path";
    case CorridorStatus::kSeedInCollision:
      return "seed_in_collision";
  }
  return "?";
}

CorridorBuilder::CorridorBuilder(const CorridorConfig& cfg) : cfg_(cfg) { cfg_.validate(); }

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> CorridorBuilder::seeds(
    const std::vector<Eigen::Vector3d>& path) const {
  std::vector<Eigen::Vector3d> pts;
  for (const auto& p : path)
    if (pts.empty() || (p - pts.back()).norm() > 1e-6) pts.push_back(p);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> out;
  if (pts.size() == 1) out.emplace_back(pts[0], pts[0]);
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const double len = (pts[i + 1] - pts[i]).norm();
    const int k = std::max(1, static_cast<int>(std::ceil(len / cfg_.max_seed_length_m - 1e-9)));
    for (int j = 0; j < k; ++j)
      out.emplace_back(pts[i] + (pts[i + 1] - pts[i]) * (double(j) / k),
                       pts[i] + (pts[i + 1] - pts[i]) * (double(j + 1) / k));
  }
  return out;
}

CorridorResult CorridorBuilder::build(const std::vector<Eigen::Vector3d>& path,
                                      const LocalGrid& grid) const {
  std::vector<Eigen::Vector3d> obstacles;
  CorridorResult res;
  const auto segs = seeds(path);
  if (segs.empty()) return res;
  res.status = CorridorStatus::kOk;
  const Eigen::Vector3d wlo = grid.windowMin(), whi = grid.windowMax();
  for (const auto& [a, b] : segs) {
    const Eigen::Vector3d lo = a.cwiseMin(b).array() - cfg_.box_margin_m;
    const Eigen::Vector3d hi = a.cwiseMax(b).array() + cfg_.box_margin_m;
    obstacles.clear();
    // Obstacles just outside the box are still within clearance of its faces: gather them too.
    // Interior cells can be skipped when the clearance spans two cells (see local_grid.h).
    grid.occupiedCentersInBox(lo.array() - cfg_.clearance_m, hi.array() + cfg_.clearance_m,
                              obstacles, cfg_.clearance_m >= 2.0 * grid.resolution());
    if (cfg_.blind_depth_m > 0.0) {
      // Below the seed's height at the nearest point of its horizontal projection.
      const Eigen::Vector2d axy = a.head<2>(), dxy = b.head<2>() - a.head<2>();
      const double len_sq = dxy.squaredNorm();
      const auto blind_top_z = [&](double x, double y) {
        if (len_sq <= 1e-12) return std::min(a.z(), b.z()) - cfg_.blind_depth_m;
        const double t = std::clamp((Eigen::Vector2d(x, y) - axy).dot(dxy) / len_sq, 0.0, 1.0);
        return a.z() + t * (b.z() - a.z()) - cfg_.blind_depth_m;
      };
      grid.unobservedTopsBelow(lo.array() - cfg_.clearance_m, hi.array() + cfg_.clearance_m,
                               blind_top_z, obstacles);
    }
    bool in_collision = false;
    res.polytopes.push_back(
        inflateSegment(a, b, obstacles, lo.cwiseMax(wlo).cwiseMin(a.cwiseMin(b)),
                       hi.cwiseMin(whi).cwiseMax(a.cwiseMax(b)), &in_collision));
    if (in_collision) res.status = CorridorStatus::kSeedInCollision;
  }
  return res;
}

CorridorResult CorridorBuilder::build(const std::vector<Eigen::Vector3d>& path,
                                      const std::vector<Eigen::Vector3d>& obstacles,
                                      const Eigen::Vector3d& bound_lo,
                                      const Eigen::Vector3d& bound_hi) const {
  CorridorResult res;
  const auto segs = seeds(path);
  if (segs.empty()) return res;
  res.status = CorridorStatus::kOk;
  std::vector<Eigen::Vector3d> local;
  for (const auto& [a, b] : segs) {
    const Eigen::Vector3d lo = a.cwiseMin(b).array() - cfg_.box_margin_m;
    const Eigen::Vector3d hi = a.cwiseMax(b).array() + cfg_.box_margin_m;
    local.clear();
    const Eigen::Vector3d glo = lo.array() - cfg_.clearance_m, ghi = hi.array() + cfg_.clearance_m;
    for (const auto& o : obstacles)
      if ((o.array() >= glo.array()).all() && (o.array() <= ghi.array()).all()) local.push_back(o);
    bool in_collision = false;
    res.polytopes.push_back(
        inflateSegment(a, b, local, lo.cwiseMax(bound_lo).cwiseMin(a.cwiseMin(b)),
                       hi.cwiseMin(bound_hi).cwiseMax(a.cwiseMax(b)), &in_collision));
    if (in_collision) res.status = CorridorStatus::kSeedInCollision;
  }
  return res;
}

namespace {

inline Eigen::Vector3d closestOnSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                        const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = b - a;
  const double l2 = ab.squaredNorm();
  if (l2 < 1e-18) return a;
  const double s = std::clamp((p - a).dot(ab) / l2, 0.0, 1.0);
  return a + s * ab;
}

// Barrier objective of the inscribed-ellipsoid problem; x = (d, s1, l21, s2, l31, l32, s3) with
// the diagonal of L as exp(s) so that L stays positive definite.
struct MvieBarrier {
  const MatX3& A;
  const Eigen::VectorXd& b;
  double t;

  static Eigen::Matrix3d lower(const Eigen::Matrix<double, 9, 1>& x) {
    Eigen::Matrix3d L = Eigen::Matrix3d::Zero();
    L(0, 0) = std::exp(x(3));
    L(1, 0) = x(4);
    L(1, 1) = std::exp(x(5));
    L(2, 0) = x(6);
    L(2, 1) = x(7);
    L(2, 2) = std::exp(x(8));
    return L;
  }
  // Returns +inf outside the domain.
  double value(const Eigen::Matrix<double, 9, 1>& x, Eigen::Matrix<double, 9, 1>* g) const {
    const Eigen::Matrix3d L = lower(x);
    const Eigen::Vector3d d = x.head<3>();
    double f = -t * (x(3) + x(5) + x(8));
    Eigen::Matrix3d gL = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gd = Eigen::Vector3d::Zero();
    for (int i = 0; i < A.rows(); ++i) {
      const Eigen::Vector3d a = A.row(i).transpose();
      const Eigen::Vector3d w = L.transpose() * a;
      const double nw = w.norm();
      const double slack = b(i) - a.dot(d) - nw;
      if (!(slack > 0.0)) return std::numeric_limits<double>::infinity();
      f -= std::log(slack);
      if (g) {
        gd += a / slack;
        if (nw > 1e-300) gL += (a * w.transpose()) / (nw * slack);
      }
    }
    if (g) {
      (*g).head<3>() = gd;
      (*g)(3) = -t + gL(0, 0) * L(0, 0);
      (*g)(4) = gL(1, 0);
      (*g)(5) = -t + gL(1, 1) * L(1, 1);
      (*g)(6) = gL(2, 0);
      (*g)(7) = gL(2, 1);
      (*g)(8) = -t + gL(2, 2) * L(2, 2);
    }
    return f;
  }
};

}  // namespace

bool maxVolumeInscribedEllipsoid(const MatX3& A, const Eigen::VectorXd& b,
                                 const Eigen::Vector3d& x0, int newton_steps, Eigen::Matrix3d* C,
                                 Eigen::Vector3d* d) {
  using Vec9 = Eigen::Matrix<double, 9, 1>;
  const double min_slack = (b - A * x0).minCoeff();
  if (!(min_slack > 1e-9)) return false;
  Vec9 x = Vec9::Zero();
  x.head<3>() = x0;
  const double r0 = std::log(0.5 * min_slack);
  x(3) = x(5) = x(8) = r0;
  const int m = static_cast<int>(A.rows());
  // Two points of the central path: t = m then 20 m (log-volume gap about m / t).
  for (double t : {1.0 * m, 20.0 * m}) {
    MvieBarrier fb{A, b, t};
    for (int it = 0; it < newton_steps; ++it) {
      Vec9 g, gp;
      const double f = fb.value(x, &g);
      // Hessian by forward differences of the analytic gradient (9 extra gradient evaluations).
      Eigen::Matrix<double, 9, 9> H;
      for (int k = 0; k < 9; ++k) {
        Vec9 xp = x;
        const double h = 1e-6 * std::max(1.0, std::abs(x(k)));
        xp(k) += h;
        if (!std::isfinite(fb.value(xp, &gp))) {
          xp(k) = x(k) - h;
          fb.value(xp, &gp);
          H.col(k) = (g - gp) / h;
        } else {
          H.col(k) = (gp - g) / h;
        }
      }
      H = 0.5 * (H + H.transpose()).eval();
      Eigen::LDLT<Eigen::Matrix<double, 9, 9>> ldlt(H +
                                                    1e-9 * Eigen::Matrix<double, 9, 9>::Identity());
      Vec9 dx = -ldlt.solve(g);
      if (!dx.allFinite() || g.dot(dx) >= 0.0) dx = -g;
      const double decrement = -g.dot(dx);
      if (decrement < 1e-8) break;
      double step = 1.0;
      bool moved = false;
      for (int ls = 0; ls < 30; ++ls) {
        const Vec9 xn = x + step * dx;
        const double fn = fb.value(xn, nullptr);
        if (std::isfinite(fn) && fn <= f - 0.25 * step * decrement) {
          x = xn;
          moved = true;
          break;
        }
        step *= 0.5;
      }
      if (!moved) break;
    }
  }
  *C = MvieBarrier::lower(x);
  *d = x.head<3>();
  return true;
}

Polytope CorridorBuilder::inflateSegment(const Eigen::Vector3d& sa, const Eigen::Vector3d& sb,
                                         const std::vector<Eigen::Vector3d>& obstacles,
                                         const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                         bool* in_collision) const {
  Polytope poly;
  poly.seed_start_m = sa;
  poly.seed_end_m = sb;
  *in_collision = false;
  // Initial ellipsoid: along the seed, thin across it.
  const Eigen::Vector3d axis = sb - sa;
  const double len = axis.norm();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (len > 1e-9) {
    R = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), axis / len).toRotationMatrix();
  }
  const double r = cfg_.initial_radius_m;
  Eigen::Matrix3d C = R * Eigen::Vector3d(0.5 * len + r, r, r).asDiagonal();
  Eigen::Vector3d d = 0.5 * (sa + sb);

  const int n = static_cast<int>(obstacles.size());
  std::vector<std::pair<Eigen::Vector3d, double>> remaining;
  std::vector<Eigen::Vector3d> normals;
  std::vector<double> offsets;
  for (int iter = 0; iter < cfg_.iterations; ++iter) {
    normals.clear();
    offsets.clear();
    poly.clearance_reduced = false;
    for (int a = 0; a < 3; ++a) {  // bounding box, always containing the seed
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[a] = 1.0;
      normals.push_back(e);
      offsets.push_back(hi[a]);
      normals.push_back(-e);
      offsets.push_back(-lo[a]);
    }
    const Eigen::Matrix3d Cinv = C.inverse();
    // Remaining obstacles, compacted as planes handle them; each plane costs one pass that also
    // finds the nearest remaining point (in the ellipsoid metric) for the next plane.
    remaining.resize(n);
    for (int i = 0; i < n; ++i)
      remaining[i] = {obstacles[i], (Cinv * (obstacles[i] - d)).squaredNorm()};
    int best = -1;
    double best_d = 1e300;
    for (int i = 0; i < n; ++i)
      if (remaining[i].second < best_d) best_d = remaining[i].second, best = i;
    while (best >= 0) {
      const Eigen::Vector3d o = remaining[best].first;
      // The seed-separating plane leaves the seed a margin of dist(o, seed) - clearance, the most
      // any plane through o can. The IRIS tangent plane (better for volume) is taken only if it
      // leaves at least half of that, so that the corridor never pinches the seed.
      const Eigen::Vector3d c = closestOnSegment(sa, sb, o);
      const double dn = (o - c).norm();
      bool skip = false;
      Eigen::Vector3d nrm = Cinv.transpose() * (Cinv * (o - d));  // IRIS tangent plane normal
      double seed_max = 0.0;
      bool tangent_ok = nrm.norm() > 1e-12;
      if (tangent_ok) {
        nrm.normalize();
        seed_max = std::max(nrm.dot(sa), nrm.dot(sb));
        const double wanted = cfg_.clearance_m + 0.5 * std::max(0.0, dn - cfg_.clearance_m);
        tangent_ok = seed_max <= nrm.dot(o) - wanted;
      }
      if (!tangent_ok) {
        if (dn < 1e-9) {
          *in_collision = true;  // nothing can separate a point on the seed
          skip = true;
        } else {
          nrm = (o - c) / dn;
          seed_max = std::max(nrm.dot(sa), nrm.dot(sb));
        }
      }
      const double off = skip ? 0.0 : nrm.dot(o);
      if (!skip) {
        double shifted = off - cfg_.clearance_m;
        if (shifted < seed_max) {
          shifted = seed_max;
          poly.clearance_reduced = true;
        }
        normals.push_back(nrm);
        offsets.push_back(shifted);
      }
      size_t keep = 0;
      best = -1;
      best_d = 1e300;
      for (size_t j = 0; j < remaining.size(); ++j) {
        const auto& r = remaining[j];
        if (skip ? (r.first == o) : (nrm.dot(r.first) >= off - 1e-12)) continue;  // handled
        if (r.second < best_d) best_d = r.second, best = static_cast<int>(keep);
        remaining[keep++] = r;
      }
      remaining.resize(keep);
    }
    poly.A.resize(static_cast<int>(normals.size()), 3);
    poly.b.resize(static_cast<int>(normals.size()));
    for (size_t k = 0; k < normals.size(); ++k) {
      poly.A.row(k) = normals[k].transpose();
      poly.b(k) = offsets[k];
    }
    if (iter + 1 == cfg_.iterations) break;  // the last polytope needs no new ellipsoid
    Eigen::Matrix3d Cn;
    Eigen::Vector3d dn;
    if (!maxVolumeInscribedEllipsoid(poly.A, poly.b, 0.5 * (sa + sb), cfg_.mvie_newton_steps, &Cn,
                                     &dn))
      break;  // seed midpoint on the boundary: keep the current polytope
    C = Cn;
    d = dn;
  }
  poly.ellipsoid_C = C;
  poly.ellipsoid_d = d;
  return poly;
}

}  // namespace efs::traj
