// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/dbscan.h"

namespace efs::registration {

std::vector<int> dbscan(size_t n, double eps, size_t min_points,
                        const std::function<double(size_t, size_t)>& distance) {
  constexpr int kUnvisited = -2;
  std::vector<int> label(n, kUnvisited);
  std::vector<std::vector<size_t>> neighbours(n);
  for (size_t i = 0; i < n; ++i) {
    neighbours[i].push_back(i);
    for (size_t j = i + 1; j < n; ++j) {
      if (distance(i, j) <= eps) {
        neighbours[i].push_back(j);
        neighbours[j].push_back(i);
      }
    }
  }
  int cluster = 0;
  for (size_t i = 0; i < n; ++i) {
    if (label[i] != kUnvisited) continue;
    if (neighbours[i].size() < min_points) {
      label[i] = kDbscanNoise;
      continue;
    }
    label[i] = cluster;
    std::vector<size_t> frontier(neighbours[i].begin(), neighbours[i].end());
    while (!frontier.empty()) {
      const size_t j = frontier.back();
      frontier.pop_back();
      if (label[j] == kDbscanNoise) label[j] = cluster;  // border point
      if (label[j] != kUnvisited) continue;
      label[j] = cluster;
      if (neighbours[j].size() >= min_points) {
        frontier.insert(frontier.end(), neighbours[j].begin(), neighbours[j].end());
      }
    }
    ++cluster;
  }
  return label;
}

}  // namespace efs::registration
