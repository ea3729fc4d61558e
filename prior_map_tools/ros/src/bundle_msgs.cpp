// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools_ros/bundle_msgs.h"

#include "efs_common_ros/cloud_conversions.h"

namespace efs::prior_map {

sensor_msgs::PointCloud2 toPointCloud2(const std::vector<Eigen::Vector2d>& points_m,
                                       const std_msgs::Header& header) {
  std::vector<Eigen::Vector3f> points;
  points.reserve(points_m.size());
  for (const auto& p : points_m)
    points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f);
  return ros_common::toPointCloud2(points, header);
}

explore_from_sketch::Guidepoints toGuidepointsMsg(const PriorBundle& bundle,
                                                  const std_msgs::Header& header) {
  explore_from_sketch::Guidepoints msg;
  msg.header = header;
  for (const auto& g : bundle.guidepoints) {
    msg.ids.push_back(g.id);
    geometry_msgs::Point p;
    p.x = g.position_m.x();
    p.y = g.position_m.y();
    msg.positions.push_back(p);
    msg.states.push_back(explore_from_sketch::Guidepoints::UNEXPLORED);
  }
  return msg;
}

visualization_msgs::MarkerArray toGuidepointMarkers(const PriorBundle& bundle,
                                                    const std_msgs::Header& header) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker spheres;
  spheres.header = header;
  spheres.ns = "guidepoints";
  spheres.id = 0;
  spheres.type = visualization_msgs::Marker::SPHERE_LIST;
  spheres.action = visualization_msgs::Marker::ADD;
  spheres.pose.orientation.w = 1.0;
  const double size = std::max(0.5, 0.05 * bundle.mapping_range_m);
  spheres.scale.x = spheres.scale.y = spheres.scale.z = size;
  spheres.color.r = 1.0f;
  spheres.color.g = 0.55f;
  spheres.color.a = 1.0f;
  for (const auto& g : bundle.guidepoints) {
    geometry_msgs::Point p;
    p.x = g.position_m.x();
    p.y = g.position_m.y();
    spheres.points.push_back(p);
    visualization_msgs::Marker label;
    label.header = header;
    label.ns = "guidepoint_ids";
    label.id = static_cast<int>(g.id);
    label.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    label.action = visualization_msgs::Marker::ADD;
    label.pose.position = p;
    label.pose.position.z = size;
    label.pose.orientation.w = 1.0;
    label.scale.z = size;
    label.color.r = label.color.g = label.color.b = 1.0f;
    label.color.a = 1.0f;
    label.text = std::to_string(g.id);
    out.markers.push_back(label);
  }
  out.markers.push_back(spheres);
  return out;
}

visualization_msgs::MarkerArray toPrmMarkers(const PriorBundle& bundle,
                                             const std_msgs::Header& header) {
  visualization_msgs::Marker lines;
  lines.header = header;
  lines.ns = "prm";
  lines.id = 0;
  lines.type = visualization_msgs::Marker::LINE_LIST;
  lines.action = visualization_msgs::Marker::ADD;
  lines.pose.orientation.w = 1.0;
  lines.scale.x = 0.05;
  lines.color.r = 0.6f;
  lines.color.g = 0.75f;
  lines.color.b = 0.9f;
  lines.color.a = 0.6f;
  for (const auto& e : bundle.prm.edges) {
    for (int idx : {e.a, e.b}) {
      geometry_msgs::Point p;
      p.x = bundle.prm.nodes_m[idx].x();
      p.y = bundle.prm.nodes_m[idx].y();
      lines.points.push_back(p);
    }
  }
  visualization_msgs::MarkerArray out;
  out.markers.push_back(lines);
  return out;
}

nav_msgs::OccupancyGrid toOccupancyGrid(const PriorBundle& bundle, const std_msgs::Header& header) {
  nav_msgs::OccupancyGrid grid;
  grid.header = header;
  grid.info.map_load_time = header.stamp;
  grid.info.resolution = static_cast<float>(bundle.frame.m_per_px);
  grid.info.width = static_cast<uint32_t>(bundle.frame.width_px);
  grid.info.height = static_cast<uint32_t>(bundle.frame.height_px);
  grid.info.origin.position.x = bundle.frame.origin_m.x();
  grid.info.origin.position.y = bundle.frame.origin_m.y();
  grid.info.origin.orientation.w = 1.0;
  grid.data.resize(static_cast<size_t>(grid.info.width) * grid.info.height);
  // OccupancyGrid rows run upwards from the origin; image rows run downwards.
  for (int r = 0; r < bundle.frame.height_px; ++r) {
    const int grid_row = bundle.frame.height_px - 1 - r;
    for (int c = 0; c < bundle.frame.width_px; ++c) {
      grid.data[static_cast<size_t>(grid_row) * grid.info.width + c] =
          bundle.traversable(r, c) ? 0 : 100;
    }
  }
  return grid;
}

}  // namespace efs::prior_map
