// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/frontier_clusters.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <tuple>
#include <unordered_set>

#include "efs_common/config_check.h"

namespace efs::planner {

void FrontierClusterConfig::validate() const {
  requireInRange("frontier.max_cluster_cells", max_cluster_cells, 2, 1000000);
  requirePositive("frontier.max_cluster_extent_m", max_cluster_extent_m);
  requireInRange("frontier.min_cluster_cells", min_cluster_cells, 1, max_cluster_cells);
}

FrontierClusterer::FrontierClusterer(FrontierClusterConfig config) : config_(config) {
  config_.validate();
}

int FrontierClusterer::clusterOf(const VoxelKey& k) const {
  auto it = cell_cluster_.find(k);
  return it == cell_cluster_.end() ? -1 : it->second;
}

FrontierUpdateStats FrontierClusterer::update(ObservationMap& map) {
  FrontierUpdateStats st;
  last_removed_.clear();
  last_created_.clear();
  const std::vector<VoxelKey> changed = map.takeFrontierChanges();
  st.changed_cells = changed.size();
  if (changed.empty()) {
    st.clusters_total = clusters_.size();
    return st;
  }
  // Dissolve every cluster that owns a changed cell or touches one: a new frontier cell next to
  // a cluster may merge it with others.
  std::unordered_set<int> dirty;
  for (const VoxelKey& k : changed) {
    const int own = clusterOf(k);
    if (own >= 0) dirty.insert(own);
    if (!map.isFrontier(k)) continue;
    for (const VoxelKey& o : neighbourOffsets26()) {
      const int c = clusterOf({k.x + o.x, k.y + o.y, k.z + o.z});
      if (c >= 0) dirty.insert(c);
    }
  }
  std::unordered_set<VoxelKey, VoxelKeyHash> pending;
  for (const VoxelKey& k : changed)
    if (map.isFrontier(k)) pending.insert(k);
  std::vector<int> dirty_sorted(dirty.begin(), dirty.end());
  std::sort(dirty_sorted.begin(), dirty_sorted.end());
  for (int id : dirty_sorted) {
    for (const VoxelKey& k : clusters_[id].cells) {
      cell_cluster_.erase(k);
      if (map.isFrontier(k)) pending.insert(k);
    }
    clusters_.erase(id);
    last_removed_.push_back(id);
  }
  // Flood fill over the pending cells, in a deterministic order (sorted seeds).
  std::vector<VoxelKey> seeds(pending.begin(), pending.end());
  std::sort(seeds.begin(), seeds.end(), [](const VoxelKey& a, const VoxelKey& b) {
    return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x);
  });
  for (const VoxelKey& seed : seeds) {
    if (!pending.count(seed)) continue;
    addCluster(takeComponent26(seed, pending), map.resolution());
  }
  st.clusters_removed = last_removed_.size();
  st.clusters_created = last_created_.size();
  st.clusters_total = clusters_.size();
  return st;
}

void FrontierClusterer::addCluster(std::vector<VoxelKey> cells, double res) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
  for (const VoxelKey& k : cells) {
    const Eigen::Vector3d c = voxelCenter(k, res);
    mean += c;
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  mean /= static_cast<double>(cells.size());
  const double extent = (hi - lo).maxCoeff();
  if (cells.size() >= 2 && (static_cast<int>(cells.size()) > config_.max_cluster_cells ||
                            extent > config_.max_cluster_extent_m)) {
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const VoxelKey& k : cells) {
      const Eigen::Vector3d d = voxelCenter(k, res) - mean;
      cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Eigen::Vector3d axis = es.eigenvectors().col(2);
    std::vector<VoxelKey> a, b;
    for (const VoxelKey& k : cells)
      (axis.dot(voxelCenter(k, res) - mean) < 0.0 ? a : b).push_back(k);
    if (!a.empty() && !b.empty()) {
      addCluster(std::move(a), res);
      addCluster(std::move(b), res);
      return;
    }
  }
  FrontierCluster c;
  c.id = next_id_++;
  c.centroid_world_m = mean;
  c.box_min_world_m = lo - Eigen::Vector3d::Constant(0.5 * res);
  c.box_max_world_m = hi + Eigen::Vector3d::Constant(0.5 * res);
  c.too_small = static_cast<int>(cells.size()) < config_.min_cluster_cells;
  for (const VoxelKey& k : cells) cell_cluster_[k] = c.id;
  c.cells = std::move(cells);
  last_created_.push_back(c.id);
  clusters_.emplace(c.id, std::move(c));
}

}  // namespace efs::planner
