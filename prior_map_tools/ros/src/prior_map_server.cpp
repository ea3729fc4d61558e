// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools_ros/prior_map_server.h"

#include <explore_from_sketch/Guidepoints.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "efs_common/config_check.h"
#include "efs_common_ros/param_reader.h"
#include "prior_map_tools/prior_map_error.h"
#include "prior_map_tools_ros/bundle_msgs.h"
#include "prior_map_tools_ros/topics.h"

namespace efs::prior_map {

PriorMapServerConfig loadPriorMapServerConfig(const ros::NodeHandle& private_nh) {
  ros_common::ParamReader p(private_nh);
  PriorMapServerConfig c;
  p.get("bundle_path", c.bundle_path);
  p.get("sketch_path", c.sketch_path);
  p.get("write_bundle", c.write_bundle);
  p.get("frame_id", c.frame_id);
  PriorMapConfig& b = c.builder;
  p.get("scale_guess_m_per_px", b.load.scale_guess_m_per_px);
  std::string kind = toString(b.load.kind);
  p.get("sketch_kind", kind);
  if (kind == "auto") {
    b.load.kind = SketchKind::kAuto;
  } else if (kind == "line_drawing") {
    b.load.kind = SketchKind::kLineDrawing;
  } else if (kind == "occupancy_grid") {
    b.load.kind = SketchKind::kOccupancyGrid;
  } else {
    throw ConfigError("parameter 'sketch_kind' = '" + kind +
                      "' must be auto, line_drawing or occupancy_grid");
  }
  p.get("wall_threshold", b.load.wall_threshold);
  p.get("mapping_range_m", b.guidepoints.mapping_range_m);
  p.get("guidepoint_interval_factor", b.guidepoints.interval_factor);
  p.get("guidepoint_region_cover_factor", b.guidepoints.region_cover_factor);
  p.get("robot_radius_m", b.traversable.robot_radius_m);
  p.get("max_outer_gap_m", b.traversable.max_outer_gap_m);
  p.get("min_region_area_m2", b.traversable.min_region_area_m2);
  p.get("min_enclosed_span_fraction", b.traversable.min_enclosed_span_fraction);
  p.get("open_outline_gap_m", b.traversable.open_outline_gap_m);
  p.get("drop_island_interiors", b.traversable.drop_island_interiors);
  p.get("spur_prune_length_m", b.skeleton.spur_prune_length_m);
  p.get("max_island_extent_m", b.skeleton.max_island_extent_m);
  p.get("prm_node_spacing_m", b.prm.node_spacing_m);
  p.get("prm_k_neighbours", b.prm.k_neighbours);
  int seed = static_cast<int>(b.prm.seed);
  p.get("prm_seed", seed);
  requireInRange("prm_seed", seed, 0, 1 << 30);
  b.prm.seed = static_cast<uint64_t>(seed);
  p.rejectUnknown();

  requireThat(!c.bundle_path.empty() || !c.sketch_path.empty(), "bundle_path",
              "set bundle_path (a .prior file) or sketch_path (an image or map_server YAML)");
  requireThat(!c.write_bundle || !c.bundle_path.empty(), "bundle_path",
              "write_bundle is true but bundle_path is empty");
  requireThat(!c.frame_id.empty(), "frame_id", "must not be empty");
  b.validate();
  return c;
}

PriorMapServer::PriorMapServer(ros::NodeHandle nh, const PriorMapServerConfig& config) {
  if (!config.sketch_path.empty()) {
    bundle_ = buildPriorBundle(loadSketch(config.sketch_path, config.builder.load), config.builder);
    if (config.write_bundle) savePriorBundle(bundle_, config.bundle_path);
  } else {
    bundle_ = loadPriorBundle(config.bundle_path);
  }
  std_msgs::Header header;
  header.frame_id = config.frame_id;
  header.stamp = ros::Time::now();

  cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>(topics::kSketchCloud, 1, true);
  guidepoints_pub_ = nh.advertise<explore_from_sketch::Guidepoints>(topics::kGuidepoints, 1, true);
  guidepoint_markers_pub_ =
      nh.advertise<visualization_msgs::MarkerArray>(topics::kGuidepointMarkers, 1, true);
  prm_markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>(topics::kPrmMarkers, 1, true);
  map_pub_ = nh.advertise<nav_msgs::OccupancyGrid>(topics::kTraversableMap, 1, true);

  cloud_pub_.publish(toPointCloud2(bundle_.wallPoints(), header));
  guidepoints_pub_.publish(toGuidepointsMsg(bundle_, header));
  guidepoint_markers_pub_.publish(toGuidepointMarkers(bundle_, header));
  prm_markers_pub_.publish(toPrmMarkers(bundle_, header));
  map_pub_.publish(toOccupancyGrid(bundle_, header));

  const PriorMapSummary s = summarize(bundle_);
  ROS_INFO("prior_map_server: %s: %d guidepoints, %d PRM nodes, region %.0f m^2 in %d component(s)",
           bundle_.source_path.c_str(), s.guidepoints, s.prm_nodes, s.region_area_m2, s.components);
}

}  // namespace efs::prior_map
