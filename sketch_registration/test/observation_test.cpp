// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The observation keeps what a person draws: a building's walls with door openings as gaps and
// no parked car; a cave's outline at the passage's widest extent, not where a slice at the
// robot's height cuts the wall.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sketch_registration/observation.h"

namespace efs::registration {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kStep = 0.2;  // the local map's voxel size

/// A room 16 x 8 m, 3 m high: floor, ceiling, walls at y = +-4 (a door 1 m wide and 2.1 m high
/// at x in [2, 3] in the y = +4 wall) and a car (2 x 2 x 1.5 m) whose footprint hides the floor.
Points3d buildingScene() {
  Points3d pts;
  const auto inCar = [](double x, double y) {
    return x >= -3 && x <= -1 && y >= -2.5 && y <= -0.5;
  };
  for (double x = -8; x <= 8 + 1e-9; x += kStep) {
    for (double y = -4; y <= 4 + 1e-9; y += kStep) {
      if (!inCar(x, y)) pts.emplace_back(x, y, 0.0);
      pts.emplace_back(x, y, 3.0);
    }
    for (double z = 0; z <= 3 + 1e-9; z += kStep) {
      pts.emplace_back(x, -4.0, z);
      const bool door = x >= 2 && x <= 3 && z < 2.1;
      if (!door) pts.emplace_back(x, 4.0, z);
    }
  }
  for (double x = -3; x <= -1 + 1e-9; x += kStep) {
    for (double y = -2.5; y <= -0.5 + 1e-9; y += kStep) pts.emplace_back(x, y, 1.5);
    for (double z = 0; z <= 1.5 + 1e-9; z += kStep) {
      pts.emplace_back(x, -2.5, z);
      pts.emplace_back(x, -0.5, z);
    }
  }
  for (double y = -2.5; y <= -0.5 + 1e-9; y += kStep) {
    for (double z = 0; z <= 1.5 + 1e-9; z += kStep) {
      pts.emplace_back(-3.0, y, z);
      pts.emplace_back(-1.0, y, z);
    }
  }
  return pts;
}

/// A tunnel along x with an elliptical cross-section (half-width 2.5 m, half-height 2 m) centred
/// `centre_z_m` up (3 m: a robot at 1.5 m sees the walls bulge out above it to |y| = 2.5).
Points3d caveScene(double centre_z_m = 3.0) {
  Points3d pts;
  for (double x = -8; x <= 8 + 1e-9; x += kStep) {
    for (double t = 0; t < 2 * M_PI; t += 0.04) {
      pts.emplace_back(x, 2.5 * std::cos(t), centre_z_m + 2.0 * std::sin(t));
    }
  }
  return pts;
}

/// The cave's wall points all lie on its outline (|y| = 2.5), along both walls' whole length.
void expectCaveOutline(const ProjectedMap& m) {
  int north = 0, south = 0;
  for (const Vector2d& p : m.points_m) {
    EXPECT_GT(std::abs(p.y()), 2.5 - 0.35) << p.transpose();
    (p.y() > 0 ? north : south) += 1;
  }
  EXPECT_GE(north, 55);
  EXPECT_GE(south, 55);
}

const Vector3d kRobot(0.3, 0.1, 1.5);

TEST(Observation, BuildingKeepsWallsAndDoorGapDropsCarFloorCeiling) {
  const ObservationConfig config;
  const ProjectedMap m = observeLocalMap(buildingScene(), kRobot, config, 30.0);
  ASSERT_FALSE(m.points_m.empty());
  int south = 0;
  for (const Vector2d& p : m.points_m) {
    // Only the walls: nothing of the floor, the ceiling or the car.
    EXPECT_NEAR(std::abs(p.y()), 4.0, 0.3) << p.transpose();
    // The door is a gap.
    if (p.y() > 0) {
      EXPECT_FALSE(p.x() > 2.3 && p.x() < 2.7) << p.transpose();
    }
    if (p.y() < 0) ++south;
  }
  // The south wall is kept along its whole length (one point per 0.25 m column).
  EXPECT_GE(south, 55);
  EXPECT_GT(m.num_passage_columns, 100u);

  // Contrast: every occupied column of the band keeps the car (and the floor and ceiling).
  ObservationConfig slice = config;
  slice.wall_columns = false;
  const ProjectedMap all = observeLocalMap(buildingScene(), kRobot, slice, 30.0);
  const auto onCar = [](const Vector2d& p) {
    return p.x() > -3.1 && p.x() < -0.9 && p.y() > -2.6 && p.y() < -0.4;
  };
  EXPECT_TRUE(std::any_of(all.points_m.begin(), all.points_m.end(), onCar));
  EXPECT_FALSE(std::any_of(m.points_m.begin(), m.points_m.end(), onCar));
}

TEST(Observation, EveryColumnIsWallPassageOrOther) {
  // The descriptor reads everything seen: each column is in exactly one list. A wall (one run
  // 2 m tall), a passage (floor and ceiling 3 m apart) and a floor patch (too short a run).
  Points3d pts;
  for (double z = 0.0; z <= 2.0 + 1e-9; z += kStep) pts.emplace_back(5.0, 0.0, z);
  pts.emplace_back(0.0, 5.0, 0.0);
  pts.emplace_back(0.0, 5.0, 3.0);
  pts.emplace_back(-5.0, 0.0, 0.0);
  pts.emplace_back(-5.0, 0.0, 0.2);
  const ProjectedMap m = observeLocalMap(pts, kRobot, ObservationConfig{}, 30.0);
  EXPECT_EQ(m.num_columns, 3u);
  ASSERT_EQ(m.points_m.size(), 1u);
  ASSERT_EQ(m.passage_m.size(), 1u);
  ASSERT_EQ(m.other_m.size(), 1u);
  EXPECT_NEAR(m.points_m[0].x(), 5.0, 1e-9);
  EXPECT_NEAR(m.passage_m[0].y(), 5.0, 1e-9);
  EXPECT_NEAR(m.other_m[0].x(), -5.0, 1e-9);
}

TEST(Observation, CaveKeepsTheOutlineAtTheWidestExtent) {
  const ObservationConfig config;
  expectCaveOutline(observeLocalMap(caveScene(), kRobot, config, 30.0));

  // Contrast: the old +-1 m slice around the robot sees the walls well inside the outline.
  ObservationConfig slice = config;
  slice.wall_columns = false;
  slice.slice_min_dz_m = -1.0;
  slice.slice_max_dz_m = 1.0;
  const ProjectedMap cut = observeLocalMap(caveScene(), kRobot, slice, 30.0);
  ASSERT_FALSE(cut.points_m.empty());
  double min_abs_y = 1e9;
  for (const Vector2d& p : cut.points_m) min_abs_y = std::min(min_abs_y, std::abs(p.y()));
  EXPECT_LT(min_abs_y, 2.0);
}

/// A box 2 x 4.5 m and 1.5 m tall (a parked car) on a floor, seen without any ceiling above it,
/// and a wall 3 m tall at x = 6.
Points3d carWithoutCeilingScene() {
  Points3d pts;
  for (double x = -4; x <= 6 + 1e-9; x += kStep) {
    for (double y = -4; y <= 4 + 1e-9; y += kStep) {
      const bool under_car = x >= 1 && x <= 3 && y >= -2.25 && y <= 2.25;
      if (!under_car) pts.emplace_back(x, y, 0.0);
    }
  }
  for (double y = -4; y <= 4 + 1e-9; y += kStep) {
    for (double z = 0; z <= 3 + 1e-9; z += kStep) pts.emplace_back(6.0, y, z);
  }
  for (double x = 1; x <= 3 + 1e-9; x += kStep) {
    for (double y = -2.25; y <= 2.25 + 1e-9; y += kStep) pts.emplace_back(x, y, 1.5);
    for (double z = 0; z <= 1.5 + 1e-9; z += kStep) {
      pts.emplace_back(x, -2.25, z);
      pts.emplace_back(x, 2.25, z);
    }
  }
  for (double y = -2.25; y <= 2.25 + 1e-9; y += kStep) {
    for (double z = 0; z <= 1.5 + 1e-9; z += kStep) {
      pts.emplace_back(1.0, y, z);
      pts.emplace_back(3.0, y, z);
    }
  }
  return pts;
}

TEST(Observation, CarSeenWithoutTheCeilingIsALowObstacleNotWall) {
  // The car's sides are runs from the floor to the roof, taller than wall_min_height_m; their
  // tops are level with the robot and nothing continues them upward.
  const Vector3d robot(-2.0, 0.0, 1.5);
  const auto onCar = [](const Vector2d& p) {
    return p.x() > 0.9 && p.x() < 3.1 && std::abs(p.y()) < 2.4;
  };
  const ProjectedMap m =
      observeLocalMap(carWithoutCeilingScene(), robot, ObservationConfig{}, 30.0);
  EXPECT_FALSE(std::any_of(m.points_m.begin(), m.points_m.end(), onCar));
  EXPECT_GT(m.num_low_obstacle_columns, 30u);
  EXPECT_TRUE(std::any_of(m.other_m.begin(), m.other_m.end(), onCar));
  // The wall stays, along its whole length.
  EXPECT_GE(std::count_if(m.points_m.begin(), m.points_m.end(),
                          [](const Vector2d& p) { return std::abs(p.x() - 6.0) < 0.2; }),
            30);

  // A robot flying low sees the car's top 0.3 m or more above it: the car is wall again (the
  // test only questions runs that end near or below the robot).
  const ProjectedMap low = observeLocalMap(carWithoutCeilingScene(), Vector3d(-2.0, 0.0, 1.1),
                                           ObservationConfig{}, 30.0);
  EXPECT_TRUE(std::any_of(low.points_m.begin(), low.points_m.end(), onCar));

  // Without the low-obstacle test the car's sides are wall.
  ObservationConfig no_test;
  no_test.wall_continuation_m = 0.0;
  const ProjectedMap all = observeLocalMap(carWithoutCeilingScene(), robot, no_test, 30.0);
  EXPECT_TRUE(std::any_of(all.points_m.begin(), all.points_m.end(), onCar));
  EXPECT_EQ(all.num_low_obstacle_columns, 0u);
}

TEST(Observation, CarUnderACeilingSeenNearbyIsALowObstacleForALowRobotToo) {
  // The robot flies below the car's roof, but the ceiling 4 m up was seen around the car (not
  // over it: the car's own columns would be passage): the car's top lies far below the ceiling
  // beside it, with nothing continuing it upward.
  Points3d pts = carWithoutCeilingScene();
  for (double x = -4; x <= 6 + 1e-9; x += kStep) {
    for (double y = -4; y <= 4 + 1e-9; y += kStep) {
      const bool over_car = x >= 0.5 && x <= 3.5 && y >= -2.75 && y <= 2.75;
      if (!over_car) pts.emplace_back(x, y, 4.0);
    }
  }
  const auto onCar = [](const Vector2d& p) {
    return p.x() > 0.9 && p.x() < 3.1 && std::abs(p.y()) < 2.4;
  };
  const ProjectedMap m = observeLocalMap(pts, Vector3d(-2.0, 0.0, 0.8), ObservationConfig{}, 30.0);
  EXPECT_FALSE(std::any_of(m.points_m.begin(), m.points_m.end(), onCar));
  EXPECT_GT(m.num_low_obstacle_columns, 30u);
  // The wall, which reaches the ceiling, stays.
  EXPECT_GE(std::count_if(m.points_m.begin(), m.points_m.end(),
                          [](const Vector2d& p) { return std::abs(p.x() - 6.0) < 0.2; }),
            30);
}

TEST(Observation, CaveWallBulgingBelowTheRobotContinuesUpward) {
  // A tunnel whose widest extent (|y| = 2.5 at z = 1) lies 1 m below the robot: the outermost
  // columns' runs end below the robot, and the wall carries on upward in the columns inside.
  const Points3d pts = caveScene(1.0);
  const ProjectedMap m = observeLocalMap(pts, Vector3d(0.3, 0.1, 2.0), ObservationConfig{}, 30.0);
  expectCaveOutline(m);
  EXPECT_EQ(m.num_low_obstacle_columns, 0u);

  // Contrast: looking for the continuation only just above the top misses it, and the outline's
  // columns below the robot are taken for low obstacles.
  ObservationConfig narrow;
  narrow.wall_continuation_m = kContinuationMinDz + 0.01;
  const ProjectedMap cut = observeLocalMap(pts, Vector3d(0.3, 0.1, 2.0), narrow, 30.0);
  EXPECT_GT(cut.num_low_obstacle_columns, 60u);
}

TEST(Observation, BandAndRangeLimitTheColumns) {
  ObservationConfig config;
  // A wall 2 m tall that lies entirely above the band is not seen; one beyond range neither.
  Points3d pts;
  for (double z = 6.0; z <= 8.0; z += kStep) pts.emplace_back(1.0, 0.0, z);
  for (double z = 0.0; z <= 2.0; z += kStep) pts.emplace_back(50.0, 0.0, z);
  for (double z = 0.0; z <= 2.0; z += kStep) pts.emplace_back(2.0, 0.0, z);
  pts.emplace_back(std::nan(""), 0.0, 1.0);
  const ProjectedMap m = observeLocalMap(pts, Vector3d(0, 0, 1.0), config, 30.0);
  ASSERT_EQ(m.points_m.size(), 1u);
  EXPECT_NEAR(m.points_m[0].x(), 2.0, 1e-9);
  EXPECT_EQ(m.num_non_finite, 1u);
}

TEST(Observation, ColumnsComeInTheOrderFirstMetWithTheirMeanAndAllTheirHeights) {
  ObservationConfig config;
  config.column_cell_m = 1.0;
  config.wall_min_height_m = 1.0;
  config.wall_max_gap_m = 0.5;
  // Column B (x in [2, 3)) is met first, then A (x in [1, 2)); their heights interleave and come
  // unsorted. A: 0.2 .. 1.4 with no gap over 0.4 -> wall. B: 0.0, 0.3, 1.2 -> a 0.9 m gap ->
  // passage. C (x in [4, 5)): 0.5 m tall -> other.
  const Points3d pts = {{2.2, 0.5, 1.2}, {1.5, 0.5, 1.4}, {1.7, 0.5, 0.2},
                        {2.6, 0.5, 0.0}, {1.2, 0.5, 0.6}, {2.4, 0.5, 0.3},
                        {1.6, 0.5, 1.0}, {4.5, 0.5, 0.5}, {4.5, 0.5, 1.0}};
  const ProjectedMap m = observeLocalMap(pts, Vector3d(0, 0, 0.5), config, 30.0);
  EXPECT_EQ(m.num_columns, 3u);
  ASSERT_EQ(m.points_m.size(), 1u);
  EXPECT_NEAR(m.points_m[0].x(), (1.5 + 1.7 + 1.2 + 1.6) / 4.0, 1e-12);
  ASSERT_EQ(m.passage_m.size(), 1u);
  EXPECT_NEAR(m.passage_m[0].x(), (2.2 + 2.6 + 2.4) / 3.0, 1e-12);
  ASSERT_EQ(m.other_m.size(), 1u);
  EXPECT_NEAR(m.other_m[0].x(), 4.5, 1e-12);
  // Without the wall test every column is a point, B (met first) before A before C.
  config.wall_columns = false;
  const ProjectedMap all = observeLocalMap(pts, Vector3d(0, 0, 0.5), config, 30.0);
  ASSERT_EQ(all.points_m.size(), 3u);
  EXPECT_NEAR(all.points_m[0].x(), (2.2 + 2.6 + 2.4) / 3.0, 1e-12);
  EXPECT_NEAR(all.points_m[1].x(), (1.5 + 1.7 + 1.2 + 1.6) / 4.0, 1e-12);
  EXPECT_NEAR(all.points_m[2].x(), 4.5, 1e-12);
}

TEST(Observation, DescriptorAndIcpInputsComeFromOneObservation) {
  ObservationConfig config;
  config.icp_range_m = 5.0;
  config.icp_max_points = 20;
  const Observation o = observe(buildingScene(), kRobot, config, 30.0);
  ASSERT_FALSE(o.descriptor_m.empty());
  // Every ICP point is an observation point (the same walls), within the ICP range, thinned.
  for (const Vector2d& p : o.icp_dense_m) {
    EXPECT_LE((p - kRobot.head<2>()).norm(), 5.0);
    EXPECT_TRUE(std::find(o.map.points_m.begin(), o.map.points_m.end(), p) != o.map.points_m.end());
  }
  EXPECT_LE(o.icp_m.size(), 20u);
  EXPECT_GT(o.descriptor_m.size(), o.icp_dense_m.size());
}

}  // namespace
}  // namespace efs::registration
