// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Topics of the prior_map_server, relative to its namespace; remap them in launch files.
#pragma once

namespace efs::prior_map::topics {

constexpr const char* kSketchCloud = "sketch_cloud";  // sensor_msgs/PointCloud2, latched
constexpr const char* kGuidepoints = "guidepoints";   // Guidepoints, latched
constexpr const char* kGuidepointMarkers = "guidepoint_markers";  // MarkerArray, latched
constexpr const char* kPrmMarkers = "prm_markers";                // MarkerArray, latched
constexpr const char* kTraversableMap = "traversable_map";        // nav_msgs/OccupancyGrid, latched

}  // namespace efs::prior_map::topics
