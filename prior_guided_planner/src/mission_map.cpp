// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/mission_map.h"

#include <octomap/OcTree.h>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <stdexcept>

#include "efs_common/config_check.h"
#include "efs_common/pcd_io.h"

namespace efs::planner {
namespace {

lio::LocalMapConfig cloudConfig(const MissionMapConfig& c) {
  lio::LocalMapConfig lc;
  lc.voxel_size_m = c.cloud_voxel_m;
  lc.max_range_m = c.max_range_m;
  return lc;
}

/// Opens `path` for writing or throws naming it.
std::ofstream openForWriting(const std::string& path) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  return out;
}

void finishWriting(std::ofstream& out, const std::string& path) {
  out.flush();
  if (!out) throw std::runtime_error("cannot write '" + path + "': write failed (disk full?)");
}

}  // namespace

void MissionMapConfig::validate() const {
  requireInRange("mission_map.cloud_voxel_m", cloud_voxel_m, 0.01, 10.0);
  requireInRange("mission_map.max_range_m", max_range_m, 0.5, 1000.0);
  requireInRange("mission_map.trajectory_spacing_m", trajectory_spacing_m, 0.0, 100.0);
}

MissionMap::MissionMap(const MissionMapConfig& config)
    : config_([&] {
        config.validate();
        return config;
      }()),
      cloud_(cloudConfig(config_)) {}

size_t MissionMap::insertScan(const Eigen::Vector3d& sensor_world_m,
                              const std::vector<Eigen::Vector3f>& points_world_m) {
  return cloud_.insert(points_world_m, sensor_world_m);
}

bool MissionMap::addPose(double time_s, const Eigen::Vector3d& p_world_m, double yaw_rad) {
  if (!std::isfinite(time_s) || !p_world_m.allFinite() || !std::isfinite(yaw_rad)) return false;
  if (!track_.empty() &&
      (p_world_m - track_.back().p_world_m).norm() < config_.trajectory_spacing_m)
    return false;
  track_.push_back({time_s, p_world_m, yaw_rad});
  return true;
}

std::pair<size_t, size_t> writeOccupancyOctomap(const OccupancyMap& occupancy,
                                                const std::string& path) {
  octomap::OcTree tree(occupancy.resolution());
  // Both grids are aligned at integer multiples of the resolution, so a cell centre lands in
  // exactly one OctoMap leaf. OctoMap calls a log-odds of 0 occupied, we call it free: the
  // values written are nudged off the threshold so both agree on every cell's state.
  tree.setOccupancyThres(0.5);
  size_t occupied = 0, free = 0;
  bool inside = true;
  occupancy.forEachKnownCell([&](const VoxelKey& k, double log_odds, OccupancyState state) {
    const Eigen::Vector3d c = occupancy.center(k);
    const bool occ = state == OccupancyState::kOccupied;
    const float v = occ ? std::max(static_cast<float>(log_odds), 0.01f)
                        : std::min(static_cast<float>(log_odds), -0.01f);
    octomap::OcTreeKey key;
    if (!tree.coordToKeyChecked(octomap::point3d(c.x(), c.y(), c.z()), key)) {
      inside = false;  // beyond OctoMap's 2^16-cell range: cannot be represented
      return;
    }
    tree.setNodeValue(key, v, true);
    (occ ? occupied : free) += 1;
  });
  if (!inside) {
    throw std::runtime_error("cannot write OctoMap '" + path +
                             "': the map reaches beyond OctoMap's range at this resolution");
  }
  tree.updateInnerOccupancy();
  tree.toMaxLikelihood();
  tree.prune();
  const std::string tmp = path + ".tmp";
  if (!tree.writeBinary(tmp)) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write OctoMap '" + path + "'");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write OctoMap '" + path + "': rename from " + tmp + " failed");
  }
  return {occupied, free};
}

SavedMissionMap MissionMap::save(const std::string& directory, const OccupancyMap& occupancy,
                                 const MapRegistration& registration) const {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec || !fs::is_directory(directory))
    throw std::runtime_error("cannot create the map folder '" + directory + "': " + ec.message());
  SavedMissionMap out;
  out.directory = directory;
  out.cloud_pcd = (fs::path(directory) / "cloud.pcd").string();
  out.occupancy_bt = (fs::path(directory) / "occupancy.bt").string();
  out.trajectory_csv = (fs::path(directory) / "trajectory.csv").string();
  out.registration_yaml = (fs::path(directory) / "registration.yaml").string();

  const std::vector<Eigen::Vector3f> points = cloud_.points();
  writePcdBinary(out.cloud_pcd, points);
  out.cloud_points = points.size();
  std::tie(out.occupied_cells, out.free_cells) = writeOccupancyOctomap(occupancy, out.occupancy_bt);

  {
    std::ofstream csv = openForWriting(out.trajectory_csv);
    csv << "time_s,x_m,y_m,z_m,yaw_rad\n";
    for (const TrackSample& s : track_)
      csv << s.time_s << ',' << s.p_world_m.x() << ',' << s.p_world_m.y() << ',' << s.p_world_m.z()
          << ',' << s.yaw_rad << '\n';
    finishWriting(csv, out.trajectory_csv);
    out.track_samples = track_.size();
  }
  {
    std::ofstream y = openForWriting(out.registration_yaml);
    y << "# Sketch-to-world transforms at the end of the mission, best first:\n"
      << "#   p_world_xy = scale * R(yaw_rad) * M * S * p_sketch_xy + [t_x_m, t_y_m],\n"
      << "# M = diag(1, -1) when reflected (a mirror-image drawing), else the identity;\n"
      << "# S stretches the sketch by `stretch` along stretch_axis_rad, shrinks it across\n"
      << "# (stretch 1: a similarity).\n"
      << "world_frame: \"" << registration.world_frame << "\"\n"
      << "sketch_frame: \"" << registration.sketch_frame << "\"\n"
      << "active_hypothesis_id: "
      << (registration.active_hypothesis_id ? std::to_string(*registration.active_hypothesis_id)
                                            : std::string("null"))
      << "  # the last one the planner's guidance used; null = none (prior-free)\n"
      << "hypotheses:" << (registration.hypotheses.empty() ? " []\n" : "\n");
    for (const Hypothesis& h : registration.hypotheses) {
      const Sim2& T = h.T_world_sketch;
      y << "  - {id: " << h.id << ", yaw_rad: " << T.yaw_rad << ", scale: " << T.scale
        << ", t_x_m: " << T.t_m.x() << ", t_y_m: " << T.t_m.y()
        << ", reflected: " << (T.reflected ? "true" : "false") << ", stretch: " << T.stretch
        << ", stretch_axis_rad: " << T.stretch_axis_rad << ", confidence: " << h.confidence
        << "}\n";
    }
    finishWriting(y, out.registration_yaml);
  }
  return out;
}

}  // namespace efs::planner
