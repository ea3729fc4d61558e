// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common_ros/cloud_conversions.h"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <stdexcept>

namespace efs::ros_common {

std::vector<Eigen::Vector3f> fromPointCloud2(const sensor_msgs::PointCloud2& cloud) {
  for (const char* name : {"x", "y", "z"}) {
    bool ok = false;
    for (const auto& f : cloud.fields)
      ok = ok || (f.name == name && f.datatype == sensor_msgs::PointField::FLOAT32);
    if (!ok) throw std::runtime_error(std::string("cloud has no float32 field '") + name + "'");
  }
  const size_t n = static_cast<size_t>(cloud.width) * cloud.height;
  if (cloud.point_step == 0 || cloud.data.size() < n * cloud.point_step ||
      cloud.row_step < cloud.width * cloud.point_step) {
    throw std::runtime_error("cloud data (" + std::to_string(cloud.data.size()) +
                             " bytes) is shorter than width x height x point_step");
  }
  std::vector<Eigen::Vector3f> out;
  out.reserve(n);
  sensor_msgs::PointCloud2ConstIterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  for (size_t i = 0; i < n; ++i, ++x, ++y, ++z) out.emplace_back(*x, *y, *z);
  return out;
}

sensor_msgs::PointCloud2 toPointCloud2(const std::vector<Eigen::Vector3f>& points,
                                       const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header;
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2FieldsByString(1, "xyz");
  modifier.resize(points.size());
  cloud.height = 1;
  cloud.width = static_cast<uint32_t>(points.size());
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  for (const auto& p : points) {
    *x = p.x();
    *y = p.y();
    *z = p.z();
    ++x;
    ++y;
    ++z;
  }
  return cloud;
}

}  // namespace efs::ros_common
