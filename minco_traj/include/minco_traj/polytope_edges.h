// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Vertex and edge enumeration of a small bounded polytope {x : A x <= b} for visualisation (the
// corridor as line lists). Brute force over plane triples, O(m^4) for m planes: fine for the
// tens of planes a corridor polytope has, not meant for anything larger.
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "minco_traj/corridor.h"

namespace efs::traj {

struct PolytopeSkeleton {
  std::vector<Eigen::Vector3d> vertices_m;
  std::vector<std::pair<int, int>> edges;  ///< indices into vertices_m
};

/// Vertices (merged within tol_m) and the edges between vertices that share two active planes.
/// Empty for an empty or unbounded polytope.
PolytopeSkeleton polytopeSkeleton(const Polytope& poly, double tol_m = 1e-6);

}  // namespace efs::traj
