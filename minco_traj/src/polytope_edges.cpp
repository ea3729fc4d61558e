// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj/polytope_edges.h"

#include <Eigen/LU>
#include <algorithm>

namespace efs::traj {

PolytopeSkeleton polytopeSkeleton(const Polytope& poly, double tol_m) {
  PolytopeSkeleton out;
  const int m = poly.planeCount();
  std::vector<std::vector<int>> active;  // planes through each vertex
  for (int i = 0; i < m; ++i)
    for (int j = i + 1; j < m; ++j)
      for (int k = j + 1; k < m; ++k) {
        Eigen::Matrix3d M;
        M.row(0) = poly.A.row(i);
        M.row(1) = poly.A.row(j);
        M.row(2) = poly.A.row(k);
        const Eigen::FullPivLU<Eigen::Matrix3d> lu(M);
        if (!lu.isInvertible()) continue;
        const Eigen::Vector3d x = lu.solve(Eigen::Vector3d(poly.b(i), poly.b(j), poly.b(k)));
        if (!x.allFinite() || poly.violation(x) > tol_m) continue;
        int v = 0;
        while (v < static_cast<int>(out.vertices_m.size()) &&
               (out.vertices_m[v] - x).norm() > 10.0 * tol_m)
          ++v;
        if (v == static_cast<int>(out.vertices_m.size())) {
          out.vertices_m.push_back(x);
          active.emplace_back();
        }
        for (int p : {i, j, k})
          if (std::find(active[v].begin(), active[v].end(), p) == active[v].end())
            active[v].push_back(p);
      }
  const int n = static_cast<int>(out.vertices_m.size());
  for (int u = 0; u < n; ++u)
    for (int v = u + 1; v < n; ++v) {
      int shared = 0;
      for (int p : active[u]) shared += std::count(active[v].begin(), active[v].end(), p);
      if (shared >= 2) out.edges.emplace_back(u, v);
    }
  return out;
}

}  // namespace efs::traj
