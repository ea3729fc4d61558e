// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// record_flight: flies one simulated exploration in-process (as explore_mission does) and
// records what FAST-LIO2 would have published — /cloud_registered and /Odometry in camera_init —
// plus the ground truth and /clock, to a rosbag, so that replays and regression tests run on real
// bags. No ROS master is needed: the bag is written directly.
#include <rosbag/bag.h>
#include <rosgraph_msgs/Clock.h>

#include <iostream>

#include "efs_common/cli_args.h"
#include "exploration_mission/mission_spec.h"
#include "marsim_worlds_ros/lio_messages.h"

namespace {

constexpr const char* kUsage =
    R"(usage: record_flight --bag OUT.bag [--duration S] [mission options of explore_mission]

Records a simulated exploration flight (in simulated time, as fast as the CPU allows):
  /cloud_registered (sensor_msgs/PointCloud2, frame camera_init)   as FAST-LIO2
  /Odometry         (nav_msgs/Odometry, camera_init -> body)        as FAST-LIO2
  /ground_truth/odom (nav_msgs/Odometry, world_truth -> body)
  /clock
The flight is the product's own exploration with a sketch the product draws (--variant,
default deformed) by --method (default proposed), stopped after --duration simulated seconds
(default 60).
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace efs;
  try {
    std::set<std::string> options = mission::missionSpecOptions();
    options.insert({"bag", "duration"});
    const CliArgs args(argc, argv, options, {"help"});
    if (args.flag("help") || argc == 1) {
      std::cout << kUsage;
      return argc == 1 ? 2 : 0;
    }
    const std::string bag_path = args.required("bag");
    const mission::MissionSpec spec = mission::missionSpecFromArgs(args);
    mission::MissionConfig config;
    config.record_map = false;
    config.session.coverage_enabled = false;  // not needed for a recording
    config.time_limit_s = args.number("duration", 60.0);
    const auto mission = mission::makeMission(spec, config);

    rosbag::Bag bag(bag_path, rosbag::bagmode::Write);
    sim::LioMessages messages;
    size_t scans = 0, odoms = 0;
    mission->setStepObserver([&](const sim::Simulator& sim) {
      const ros::Time now(sim.time_s());
      rosgraph_msgs::Clock clock;
      clock.clock = now;
      bag.write("/clock", now, clock);
      if (auto odom = messages.newOdometry(sim)) {
        bag.write("/Odometry", odom->header.stamp, *odom);
        bag.write("/ground_truth/odom", now, messages.groundTruth(sim));
        ++odoms;
      }
      if (auto scan = messages.newScan(sim)) {
        bag.write("/cloud_registered", scan->header.stamp, *scan);
        ++scans;
      }
    });
    const mission::MissionLog& log = mission->run();
    bag.close();
    std::cout << "record_flight: " << bag_path << ": " << log.end_time_s << " s simulated, "
              << scans << " scans, " << odoms << " odometry messages, flight "
              << log.flight_distance_m << " m (" << mission::toString(log.end) << ")\n";
    return log.end == mission::MissionEnd::kCollision ? 3 : 0;
  } catch (const std::exception& e) {
    std::cerr << "record_flight: " << e.what() << "\n";
    return 2;
  }
}
