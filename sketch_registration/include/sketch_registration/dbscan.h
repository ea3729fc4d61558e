// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// DBSCAN over an arbitrary distance (the registration clusters Sim2 transforms with d_T).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

namespace efs::registration {

constexpr int kDbscanNoise = -1;

/// Labels 0..k-1 per item, kDbscanNoise for noise. A point is core when at least `min_points`
/// items (itself included) lie within `eps`. O(n^2) distance evaluations.
std::vector<int> dbscan(size_t n, double eps, size_t min_points,
                        const std::function<double(size_t, size_t)>& distance);

}  // namespace efs::registration
