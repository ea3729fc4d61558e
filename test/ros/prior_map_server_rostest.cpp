// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Live interface of prior_map_server: it publishes, latched, the sketch cloud, the guidepoints
// (ids, positions, states), their markers, the PRM and the traversable map, all in the sketch
// frame.
#include <explore_from_sketch/Guidepoints.h>
#include <gtest/gtest.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "ros_test_utils.h"

namespace {

using efs::rostest::waitForMessage;

TEST(PriorMapServer, PublishesTheLatchedPrior) {
  ros::NodeHandle nh;
  const auto cloud = waitForMessage<sensor_msgs::PointCloud2>(nh, "prior/sketch_cloud", 20.0);
  ASSERT_TRUE(cloud);
  EXPECT_EQ(cloud->header.frame_id, "sketch");
  EXPECT_GT(cloud->width, 1000u);

  const auto gps = waitForMessage<explore_from_sketch::Guidepoints>(nh, "prior/guidepoints", 5.0);
  ASSERT_TRUE(gps);
  EXPECT_GE(gps->ids.size(), 20u);
  EXPECT_EQ(gps->ids.size(), gps->positions.size());
  EXPECT_EQ(gps->ids.size(), gps->states.size());
  for (uint8_t s : gps->states) EXPECT_EQ(s, explore_from_sketch::Guidepoints::UNEXPLORED);

  const auto map = waitForMessage<nav_msgs::OccupancyGrid>(nh, "prior/traversable_map", 5.0);
  ASSERT_TRUE(map);
  EXPECT_EQ(map->data.size(), static_cast<size_t>(map->info.width) * map->info.height);
  // Every guidepoint lies on a traversable cell.
  for (const auto& p : gps->positions) {
    const int c = static_cast<int>((p.x - map->info.origin.position.x) / map->info.resolution);
    const int r = static_cast<int>((p.y - map->info.origin.position.y) / map->info.resolution);
    ASSERT_GE(c, 0);
    ASSERT_GE(r, 0);
    EXPECT_EQ(map->data[static_cast<size_t>(r) * map->info.width + c], 0);
  }

  const auto markers =
      waitForMessage<visualization_msgs::MarkerArray>(nh, "prior/guidepoint_markers", 5.0);
  ASSERT_TRUE(markers);
  EXPECT_EQ(markers->markers.size(), gps->ids.size() + 1);
  const auto prm = waitForMessage<visualization_msgs::MarkerArray>(nh, "prior/prm_markers", 5.0);
  ASSERT_TRUE(prm);
  ASSERT_EQ(prm->markers.size(), 1u);
  EXPECT_GT(prm->markers[0].points.size(), 1000u);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "prior_map_server_rostest");
  return RUN_ALL_TESTS();
}
