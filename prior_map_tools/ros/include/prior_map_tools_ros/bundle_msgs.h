// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Prior bundle -> ROS messages, all in the sketch's own metric frame.
#pragma once

#include <explore_from_sketch/Guidepoints.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

#include "prior_map_tools/prior_bundle.h"

namespace efs::prior_map {

/// XYZ cloud (z = 0) of 2D points.
sensor_msgs::PointCloud2 toPointCloud2(const std::vector<Eigen::Vector2d>& points_m,
                                       const std_msgs::Header& header);

/// All guidepoints, every state UNEXPLORED (the planner owns the live states).
explore_from_sketch::Guidepoints toGuidepointsMsg(const PriorBundle& bundle,
                                                  const std_msgs::Header& header);

visualization_msgs::MarkerArray toGuidepointMarkers(const PriorBundle& bundle,
                                                    const std_msgs::Header& header);

visualization_msgs::MarkerArray toPrmMarkers(const PriorBundle& bundle,
                                             const std_msgs::Header& header);

/// The traversable region: 0 = traversable, 100 = not.
nav_msgs::OccupancyGrid toOccupancyGrid(const PriorBundle& bundle, const std_msgs::Header& header);

}  // namespace efs::prior_map
