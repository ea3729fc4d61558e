// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/mission_map.h"

#include <gtest/gtest.h>

#include <octomap/OcTree.h>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "efs_common/config_check.h"
#include "efs_common/pcd_io.h"
#include "efs_common/testing/paths.h"
#include "observation_map_test_scenes.h"

namespace efs::planner {
namespace {

using testing::Scene;

std::vector<Eigen::Vector3f> toFloat(const std::vector<Eigen::Vector3d>& v) {
  std::vector<Eigen::Vector3f> out;
  for (const auto& p : v) out.push_back(p.cast<float>());
  return out;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A 10 x 8 x 3 m room, scanned from two places (one on each side of the origin, so negative
// cell keys are exercised), saved, and every file read back with its own reader.
TEST(MissionMap, SavesCloudOctomapTrackAndRegistration) {
  Scene scene;
  scene.room = {{-5, -4, 0}, {5, 4, 3}};
  OccupancyMap occupancy;
  MissionMap map;
  const std::vector<Eigen::Vector3d> origins = {{-2.5, -1.5, 1.5}, {2.5, 1.5, 1.5}};
  double t = 0.0;
  for (const auto& o : origins) {
    const auto pts = scene.scanSphere(o, 2.0);
    occupancy.insertScan(o, pts);
    EXPECT_EQ(map.insertScan(o, toFloat(pts)), pts.size());
    EXPECT_TRUE(map.addPose(t, o, 0.5));
    t += 1.0;
  }
  EXPECT_FALSE(map.addPose(t, origins.back() + Eigen::Vector3d(0.05, 0, 0), 0.0));  // too close

  MapRegistration reg;
  reg.hypotheses = {{7, Sim2(0.3, 0.12, {4.0, -2.0}), 0.8}, {9, Sim2(1.0, 0.2, {0, 0}, true), 0.2}};
  reg.active_hypothesis_id = 7;
  const std::string dir = efs::testing::testOutputDir() + "/mission_map";
  std::filesystem::remove_all(dir);
  const SavedMissionMap saved = map.save(dir, occupancy, reg);

  // Dense cloud: one centroid per 0.1 m voxel, so a point lies on a wall, or (in voxels where two
  // walls meet) within the voxel's diagonal of one.
  const std::vector<Eigen::Vector3f> cloud = loadPcdPoints(saved.cloud_pcd);
  EXPECT_EQ(cloud.size(), saved.cloud_points);
  EXPECT_EQ(cloud.size(), map.cloudSize());
  EXPECT_GT(cloud.size(), 5000u);
  size_t on_wall = 0;
  for (const auto& p : cloud) {
    const double d = std::min({std::abs(p.x() + 5), std::abs(p.x() - 5), std::abs(p.y() + 4),
                               std::abs(p.y() - 4), std::abs(p.z()), std::abs(p.z() - 3)});
    ASSERT_LT(d, 0.1 * std::sqrt(3.0)) << p.transpose();
    on_wall += d < 1e-4;
  }
  EXPECT_GT(on_wall, 0.9 * cloud.size());

  // OctoMap: every known cell has the same state in the file as in the planner's map.
  octomap::OcTree tree(saved.occupancy_bt);
  EXPECT_DOUBLE_EQ(tree.getResolution(), occupancy.resolution());
  size_t checked = 0, occupied = 0;
  occupancy.forEachKnownCell([&](const VoxelKey& k, double, OccupancyState s) {
    const Eigen::Vector3d c = occupancy.center(k);
    const octomap::OcTreeNode* n = tree.search(c.x(), c.y(), c.z());
    ASSERT_NE(n, nullptr) << c.transpose();
    EXPECT_EQ(tree.isNodeOccupied(n), s == OccupancyState::kOccupied) << c.transpose();
    occupied += s == OccupancyState::kOccupied;
    ++checked;
  });
  EXPECT_EQ(checked, occupancy.numKnownCells());
  EXPECT_EQ(saved.occupied_cells, occupied);
  EXPECT_EQ(saved.occupied_cells + saved.free_cells, checked);
  EXPECT_GT(saved.occupied_cells, 500u);
  EXPECT_GT(saved.free_cells, 2000u);
  // Unknown space (outside the room, beyond its walls) stays unknown.
  EXPECT_EQ(tree.search(0.0, 0.0, 10.0), nullptr);

  const std::string csv = readAll(saved.trajectory_csv);
  EXPECT_EQ(saved.track_samples, 2u);
  EXPECT_EQ(csv.rfind("time_s,x_m,y_m,z_m,yaw_rad\n0,-2.5,-1.5,1.5,0.5\n1,2.5,1.5,1.5,0.5\n", 0),
            0u)
      << csv;

  const std::string yaml = readAll(saved.registration_yaml);
  EXPECT_NE(yaml.find("active_hypothesis_id: 7"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("{id: 7, yaw_rad: 0.29999999999999999, scale: 0.12, t_x_m: 4, t_y_m: -2, "
                      "reflected: false, stretch: 1, stretch_axis_rad: 0, "
                      "confidence: 0.80000000000000004}"),
            std::string::npos)
      << yaml;
  EXPECT_NE(yaml.find("id: 9"), std::string::npos);
  EXPECT_NE(yaml.find("reflected: true"), std::string::npos);
}

TEST(MissionMap, PriorFreeMissionWritesNoHypothesis) {
  OccupancyMap occupancy;
  MissionMap map;
  const std::string dir = efs::testing::testOutputDir() + "/mission_map_empty";
  const SavedMissionMap saved = map.save(dir, occupancy, {});
  EXPECT_EQ(saved.cloud_points, 0u);
  EXPECT_EQ(saved.occupied_cells + saved.free_cells, 0u);
  const std::string yaml = readAll(saved.registration_yaml);
  EXPECT_NE(yaml.find("active_hypothesis_id: null"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("hypotheses: []"), std::string::npos) << yaml;
  EXPECT_TRUE(loadPcdPoints(saved.cloud_pcd).empty());
}

TEST(MissionMap, BadInputIsSkippedAndBadFoldersAreNamed) {
  MissionMap map;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(map.insertScan({0, 0, 0}, {{1, 0, 0}, {nan, 0, 0}, {100, 0, 0}}), 1u);
  EXPECT_EQ(map.insertScan({nan, 0, 0}, {{1, 0, 0}}), 0u);
  EXPECT_FALSE(map.addPose(0.0, {nan, 0, 0}, 0.0));
  EXPECT_TRUE(map.track().empty());
  // A file where the folder should be.
  const std::string blocker = efs::testing::testOutputDir() + "/mission_map_blocker";
  std::ofstream(blocker) << "x";
  try {
    map.save(blocker + "/sub", OccupancyMap(), {});
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(blocker), std::string::npos) << e.what();
  }
  MissionMapConfig bad;
  bad.cloud_voxel_m = 0.0;
  try {
    MissionMap m(bad);
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("mission_map.cloud_voxel_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace efs::planner
