// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// PointCloud2 <-> Eigen point lists, shared by every node that reads or writes clouds.
#pragma once

#include <sensor_msgs/PointCloud2.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace efs::ros_common {

/// Reads x, y, z (float32) of every point. Throws std::runtime_error naming the problem if the
/// cloud has no float32 x/y/z fields or its data is shorter than its declared size.
std::vector<Eigen::Vector3f> fromPointCloud2(const sensor_msgs::PointCloud2& cloud);

sensor_msgs::PointCloud2 toPointCloud2(const std::vector<Eigen::Vector3f>& points,
                                       const std_msgs::Header& header);

}  // namespace efs::ros_common
