// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Every node's default YAML under config/ is loaded onto the parameter server and turned into its
// Config by the node's own loader: the shipped files must load cleanly, and an unknown key or an
// out-of-range value must be refused with a message naming the key.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cstdlib>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "lio_bridge_ros/lio_bridge.h"
#include "marsim_worlds_ros/marsim_node.h"
#include "minco_traj_ros/minco_traj_node.h"
#include "prior_guided_planner_ros/prior_guided_planner.h"
#include "prior_map_tools_ros/prior_map_server.h"
#include "se3_controller_ros/se3_controller_node.h"
#include "sketch_registration_ros/sketch_registration_node.h"

namespace {

struct NodeConfig {
  std::string yaml;  ///< file under config/
  /// Parameters a launch file always sets (the shipped YAML leaves them empty on purpose).
  std::vector<std::pair<std::string, std::string>> launch_params;
  std::string absurd_key;                            ///< a numeric key ...
  double absurd_value;                               ///< ... set to a value its range refuses
  std::function<void(const ros::NodeHandle&)> load;  ///< the node's loader (throws on refusal)
};

const std::vector<NodeConfig>& nodeConfigs() {
  static const std::vector<NodeConfig> configs{
      {"lio_bridge.yaml",
       {},
       "voxel_size_m",
       -0.3,
       [](const ros::NodeHandle& nh) { efs::lio::loadLioBridgeConfig(nh); }},
      {"marsim_node.yaml",
       {},
       "physics_rate_hz",
       -500.0,
       [](const ros::NodeHandle& nh) { efs::sim::loadMarsimNodeConfig(nh); }},
      {"prior_map_server.yaml",
       {{"bundle_path", "/tmp/any.prior"}},
       "mapping_range_m",
       -10.0,
       [](const ros::NodeHandle& nh) { efs::prior_map::loadPriorMapServerConfig(nh); }},
      {"sketch_registration.yaml",
       {},
       "eta",
       7.0,
       [](const ros::NodeHandle& nh) { efs::registration::loadSketchRegistrationNodeConfig(nh); }},
      {"prior_guided_planner.yaml",
       {},
       "predicted_free_spacing_m",
       -1.0,
       [](const ros::NodeHandle& nh) { efs::planner::loadPriorGuidedPlannerConfig(nh); }},
      {"minco_traj.yaml",
       {},
       "command_rate_hz",
       -100.0,
       [](const ros::NodeHandle& nh) { efs::traj::loadMincoTrajNodeConfig(nh); }},
      {"se3_controller.yaml",
       {},
       "control_rate_hz",
       -100.0,
       [](const ros::NodeHandle& nh) { efs::control::loadSe3ControllerNodeConfig(nh); }},
  };
  return configs;
}

/// Loads config/<yaml> into namespace `ns` with rosparam, as roslaunch's <rosparam load> does,
/// plus the parameters its launch file sets.
void loadYaml(const NodeConfig& c, const std::string& ns) {
  const std::string path = std::string(EFS_CONFIG_DIR) + "/" + c.yaml;
  const std::string cmd = "rosparam load " + path + " " + ns;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  for (const auto& [key, value] : c.launch_params) ros::param::set(ns + "/" + key, value);
}

std::string refusal(const NodeConfig& c, const ros::NodeHandle& nh) {
  try {
    c.load(nh);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(NodeConfigs, ShippedYamlsLoadIntoEveryConfig) {
  for (const auto& c : nodeConfigs()) {
    const std::string ns = "/shipped/" + c.yaml.substr(0, c.yaml.find('.'));
    loadYaml(c, ns);
    EXPECT_EQ(refusal(c, ros::NodeHandle(ns)), "") << c.yaml;
  }
}

TEST(NodeConfigs, UnknownKeyIsRefusedByName) {
  for (const auto& c : nodeConfigs()) {
    const std::string ns = "/unknown/" + c.yaml.substr(0, c.yaml.find('.'));
    loadYaml(c, ns);
    ros::NodeHandle nh(ns);
    nh.setParam("no_such_key_xyz", 1.0);
    const std::string why = refusal(c, nh);
    EXPECT_NE(why.find("no_such_key_xyz"), std::string::npos) << c.yaml << ": '" << why << "'";
  }
}

TEST(NodeConfigs, OutOfRangeValueIsRefusedByName) {
  for (const auto& c : nodeConfigs()) {
    const std::string ns = "/absurd/" + c.yaml.substr(0, c.yaml.find('.'));
    loadYaml(c, ns);
    ros::NodeHandle nh(ns);
    ASSERT_TRUE(nh.hasParam(c.absurd_key)) << c.yaml << " has no key " << c.absurd_key;
    nh.setParam(c.absurd_key, c.absurd_value);
    const std::string why = refusal(c, nh);
    EXPECT_NE(why.find(c.absurd_key), std::string::npos) << c.yaml << ": '" << why << "'";
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_configs_rostest");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
