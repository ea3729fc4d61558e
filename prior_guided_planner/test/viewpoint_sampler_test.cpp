// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "efs_common/config_check.h"
#include "observation_map_test_scenes.h"
#include "prior_guided_planner/frontier_clusters.h"
#include "prior_guided_planner/observation_map.h"
#include "prior_guided_planner/occupancy_map.h"
#include "prior_guided_planner/viewpoint_sampler.h"

namespace efs::planner {
namespace {

using testing::Scene;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

Eigen::Vector3d dirAt(double azimuth_deg, double elevation_deg) {
  return {std::cos(elevation_deg * kDeg) * std::cos(azimuth_deg * kDeg),
          std::cos(elevation_deg * kDeg) * std::sin(azimuth_deg * kDeg),
          std::sin(elevation_deg * kDeg)};
}

TEST(LidarFov, Mid360ElevationBandWithoutPitch) {
  LidarFovConfig c;
  c.mount_pitch_rad = 0.0;
  const LidarFov fov(c);
  EXPECT_FALSE(fov.inFov({0, 0, -1}, 0.0));  // straight below: outside -7 deg
  EXPECT_FALSE(fov.inFov({0, 0, 1}, 0.0));   // straight above: outside +52 deg
  for (double az : {0.0, 90.0, 180.0, 270.0}) {
    EXPECT_TRUE(fov.inFov(dirAt(az, 0.0), 0.0)) << az;  // 360 deg azimuth
    EXPECT_TRUE(fov.inFov(dirAt(az, -6.0), 1.0)) << az;
    EXPECT_FALSE(fov.inFov(dirAt(az, -8.0), 1.0)) << az;
    EXPECT_TRUE(fov.inFov(dirAt(az, 51.0), 2.0)) << az;
    EXPECT_FALSE(fov.inFov(dirAt(az, 53.0), 2.0)) << az;
  }
  EXPECT_TRUE(fov.sees(Eigen::Vector3d::Zero(), 0.0, Eigen::Vector3d(39, 0, 0)));
  EXPECT_FALSE(fov.sees(Eigen::Vector3d::Zero(), 0.0, Eigen::Vector3d(41, 0, 0)));
}

TEST(LidarFov, MountPitchTiltsTheBandForwardDown) {
  const LidarFov fov;  // 15 deg nose-down mount
  EXPECT_NEAR(fov.sensorElevation(dirAt(0.0, -15.0), 0.0), 0.0, 1e-12);
  EXPECT_TRUE(fov.inFov(dirAt(0.0, -15.0), 0.0));             // ahead and below: visible
  EXPECT_FALSE(fov.inFov(dirAt(180.0, -15.0), 0.0));          // behind and below: -30 deg, not
  EXPECT_TRUE(fov.inFov(dirAt(180.0, -15.0), 180.0 * kDeg));  // turn around: visible
  EXPECT_FALSE(fov.inFov({0, 0, -1}, 0.0));                   // straight below is still -75 deg
  EXPECT_TRUE(fov.inFov(dirAt(180.0, 60.0), 0.0));            // behind, high: +45 deg in the sensor
  EXPECT_FALSE(fov.inFov(dirAt(0.0, 60.0), 0.0));             // ahead, high: +75 deg, not
  EXPECT_NEAR(fov.sensorElevation(dirAt(90.0, -10.0), 0.0), -10.0 * kDeg, 0.01);  // sideways
}

// A 10 x 10 x 4 m room with a pillar at x = 2..2.5, scanned from three places.
struct ScannedRoom {
  Scene scene;
  OccupancyMap occ;
  ScannedRoom() {
    scene.room = {Eigen::Vector3d(-4.95, -4.95, 0.15), Eigen::Vector3d(5.25, 5.25, 4.05)};
    scene.solids.push_back({Eigen::Vector3d(1.95, -0.45, 0.0), Eigen::Vector3d(2.55, 0.75, 4.1)});
    for (const Eigen::Vector3d& o :
         {Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(3, 3, 2), Eigen::Vector3d(-3, -3, 2)})
      occ.insertScan(o, scene.scanSphere(o, 1.0));
  }
};

std::vector<Eigen::Vector3d> floorPatch(const Eigen::Vector3d& centre_xy) {
  std::vector<Eigen::Vector3d> cells;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      cells.emplace_back(centre_xy.x() + 0.3 * i, centre_xy.y() + 0.3 * j, 0.15);
  return cells;
}

TEST(ViewpointSampler, CellsStraightBelowAreInvisibleAndPitchDecides) {
  ScannedRoom r;
  const std::vector<Eigen::Vector3d> cells = floorPatch(Eigen::Vector3d(0.15, 0.15, 0));
  LidarFovConfig level;
  level.mount_pitch_rad = 0.0;
  const ViewpointSampler flat(ViewpointConfig{}, level);
  const ViewpointSampler pitched;  // 15 deg
  // 1.5 m above the patch: straight below, outside the band with or without the pitch.
  EXPECT_EQ(flat.scoreAt(Eigen::Vector3d(0.15, 0.15, 1.65), cells, r.occ, nullptr), 0);
  EXPECT_EQ(pitched.scoreAt(Eigen::Vector3d(0.15, 0.15, 1.65), cells, r.occ, nullptr), 0);
  // 4.5 m away and 1.05 m above: about -13 deg. The level sensor (-7 deg) misses it; the
  // pitched one sees all nine cells when facing them (yaw towards +x).
  const Eigen::Vector3d side(-4.35, 0.15, 1.2);
  EXPECT_EQ(flat.scoreAt(side, cells, r.occ, nullptr), 0);
  double yaw = 1.0;
  EXPECT_EQ(pitched.scoreAt(side, cells, r.occ, &yaw), 9);
  EXPECT_NEAR(yaw, 0.0, 0.6);
  // Facing away, the pitched sensor sees them at -28 deg: the yaw choice matters.
  EXPECT_FALSE(pitched.fov().inFov(cells[4] - side, 3.14159265358979323846));
}

TEST(ViewpointSampler, BlockedLineOfSightAndRangeDoNotCount) {
  ScannedRoom r;
  const std::vector<Eigen::Vector3d> cells = floorPatch(Eigen::Vector3d(0.15, 0.15, 0));
  const ViewpointSampler s;
  // Behind the pillar: in the FoV and in range, but the line of sight is blocked.
  const Eigen::Vector3d behind(3.45, 0.15, 1.2);
  EXPECT_TRUE(s.fov().inFov(cells[4] - behind, 3.14159265358979323846));
  EXPECT_EQ(s.scoreAt(behind, cells, r.occ, nullptr), 0);
  EXPECT_EQ(s.scoreAt(Eigen::Vector3d(-3.15, 0.15, 1.2), cells, r.occ, nullptr), 9);
  // Beyond the useful range nothing counts.
  ViewpointConfig short_range;
  short_range.useful_range_m = 3.0;
  EXPECT_EQ(ViewpointSampler(short_range)
                .scoreAt(Eigen::Vector3d(-4.35, 0.15, 1.2), cells, r.occ, nullptr),
            0);
}

TEST(ViewpointSampler, ClusterViewpointsAreSafeAndSeeTheCluster) {
  ScannedRoom r;
  FrontierCluster c;
  c.id = 7;
  for (const Eigen::Vector3d& p : floorPatch(Eigen::Vector3d(0.15, 0.15, 0)))
    c.cells.push_back(toVoxelKey(p, 0.3));
  c.centroid_world_m = Eigen::Vector3d(0.15, 0.15, 0.15);
  const ViewpointSampler s;
  const auto vps = s.sample(c, 0.3, r.occ);
  ASSERT_FALSE(vps.empty());
  EXPECT_LE(vps.size(), 2u);
  EXPECT_EQ(vps[0].visible_cells, 9);
  for (const Viewpoint& v : vps) {
    EXPECT_EQ(v.cluster_id, 7);
    EXPECT_TRUE(r.occ.isSafe(v.position_world_m, 0.5, false));
    EXPECT_GT(v.position_world_m.z(), 0.5);  // candidates under the floor were rejected
  }
}

TEST(ViewpointManager, FollowsTheFrontierOfAnExploredRoom) {
  Scene room;
  room.room = {Eigen::Vector3d(0.15, -2.85, 0.15), Eigen::Vector3d(15.75, 3.15, 3.15)};
  ObservationMapConfig strict;  // several clusters to follow, not only the far end's
  strict.facing_min_cosine = testing::kStrictFacingMinCosine;
  ObservationMap obs(strict);
  OccupancyMap occ;
  FrontierClusterer fc;
  ViewpointManager vm;
  auto step = [&](const Eigen::Vector3d& o) {
    const auto pts = room.scanSphere(o, 1.0);
    obs.insertScan(o, pts);
    occ.insertScan(o, pts);
    fc.update(obs);
    return vm.update(fc, occ, obs.resolution());
  };
  auto st = step(Eigen::Vector3d(2.0, 0.1, 1.6));
  EXPECT_EQ(st.clusters_sampled, fc.clusters().size());
  EXPECT_GT(st.viewpoints_total, 0u);
  std::set<int> ids;
  for (const Viewpoint& v : vm.all()) {
    EXPECT_TRUE(ids.insert(v.id).second);
    EXPECT_TRUE(fc.clusters().count(v.cluster_id));
    EXPECT_TRUE(occ.isSafe(v.position_world_m, 0.5, false));
    EXPECT_GT(v.visible_cells, 0);
    EXPECT_GT(v.position_world_m.x(), 2.0);  // the frontier is ahead
  }
  for (double x : {5.0, 8.0, 11.0, 14.0}) step(Eigen::Vector3d(x, 0.1, 1.6));
  EXPECT_TRUE(vm.byCluster().empty());  // nothing left to see: every viewpoint dropped
  EXPECT_TRUE(vm.all().empty());
}

// A second scan from nearly the same place rebuilds the clusters it touches; their viewpoints,
// sampled again where they were, keep their ids and places (so paths and goals stay cached).
// Without reuse every rebuilt cluster's viewpoints come back under new ids.
TEST(ViewpointManager, ResampledViewpointsKeepTheirIdsWhereTheyLandAgain) {
  Scene room;
  room.room = {Eigen::Vector3d(0.15, -2.85, 0.15), Eigen::Vector3d(15.75, 3.15, 3.15)};
  ObservationMapConfig strict;  // several clusters to rebuild
  strict.facing_min_cosine = testing::kStrictFacingMinCosine;
  for (const double reuse : {0.3, 0.0}) {
    ObservationMap obs(strict);
    OccupancyMap occ;
    FrontierClusterer fc;
    ViewpointConfig vc;
    vc.reuse_distance_m = reuse;
    ViewpointManager vm{ViewpointSampler(vc)};
    auto step = [&](const Eigen::Vector3d& o, double density) {
      const auto pts = room.scanSphere(o, density);
      obs.insertScan(o, pts);
      occ.insertScan(o, pts);
      const FrontierUpdateStats fs = fc.update(obs);
      vm.update(fc, occ, obs.resolution());
      return fs;
    };
    step(Eigen::Vector3d(2.0, 0.1, 1.6), 1.0);
    std::map<int, Eigen::Vector3d> before;
    std::set<int> clusters_before;
    for (const Viewpoint& v : vm.all()) {
      before[v.id] = v.position_world_m;
      clusters_before.insert(v.cluster_id);
    }
    ASSERT_FALSE(before.empty());
    const FrontierUpdateStats fs = step(Eigen::Vector3d(2.1, 0.1, 1.6), 1.3);
    ASSERT_GT(fs.clusters_removed, 0u);  // clusters were rebuilt
    // Viewpoints of rebuilt clusters (new cluster ids) that carry an id from before.
    int reused = 0, moved = 0;
    for (const Viewpoint& v : vm.all()) {
      const auto it = before.find(v.id);
      if (it == before.end()) continue;
      moved += (it->second - v.position_world_m).norm() > 1e-12;
      reused += !clusters_before.count(v.cluster_id);
    }
    EXPECT_EQ(moved, 0);
    if (reuse > 0.0) {
      EXPECT_GT(reused, 0) << "of " << before.size();
    } else {
      EXPECT_EQ(reused, 0);
    }
  }
}

TEST(ViewpointSampler, ConfigErrorsNameTheKey) {
  ViewpointConfig c;
  c.ring_radii_m.clear();
  EXPECT_THROW(ViewpointSampler{c}, efs::ConfigError);
  LidarFovConfig f;
  f.max_elevation_rad = -0.5;
  try {
    LidarFov fov(f);
    FAIL();
  } catch (const efs::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("lidar.max_elevation_rad"), std::string::npos);
  }
}

}  // namespace
}  // namespace efs::planner
