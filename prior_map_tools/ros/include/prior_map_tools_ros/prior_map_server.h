// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Node that provides the prior: loads a bundle (or builds one from a sketch) and publishes it,
// latched, for rviz and for nodes that only need the sketch's geometry.
#pragma once

#include <ros/ros.h>

#include <string>

#include "prior_map_tools/prior_map_builder.h"

namespace efs::prior_map {

struct PriorMapServerConfig {
  std::string bundle_path;    ///< bundle to load; or where to write one built from the sketch
  std::string sketch_path;    ///< if set, build from this sketch instead of loading
  bool write_bundle = false;  ///< with sketch_path: also save the built bundle to bundle_path
  std::string frame_id = "sketch";
  PriorMapConfig builder;  ///< used with sketch_path
};

/// Reads the node's private parameters (every key of config/prior_map_server.yaml); throws
/// efs::ConfigError naming the key on a bad or unknown one.
PriorMapServerConfig loadPriorMapServerConfig(const ros::NodeHandle& private_nh);

class PriorMapServer {
 public:
  /// Loads or builds the bundle and publishes it; throws PriorMapError / ConfigError on failure.
  PriorMapServer(ros::NodeHandle nh, const PriorMapServerConfig& config);

  const PriorBundle& bundle() const { return bundle_; }

 private:
  PriorBundle bundle_;
  ros::Publisher cloud_pub_, guidepoints_pub_, guidepoint_markers_pub_, prm_markers_pub_, map_pub_;
};

}  // namespace efs::prior_map
