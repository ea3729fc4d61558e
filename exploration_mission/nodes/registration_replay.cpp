// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// registration_replay: runs the sketch registration on a recorded flight, offline and
// deterministically, with the same core classes and decimation as lio_bridge and
// sketch_registration_node (LocalMap, FrameDecimator, SketchRegistration): every scan of the bag's
// FAST-LIO2 topics goes into the local map at the latest odometry position, and every frame due
// (0.2 Hz of bag time) goes to the registration. One line per frame: status, hypotheses, and, with
// --truth (sim_prior's FILE.truth.yaml), the best hypothesis' placement error against the truth.
// For a real flight without truth it shows what the registration would have said, frame by frame.
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>
#include <set>
#include <string>

#include "efs_common/cli_args.h"
#include "efs_common_ros/cloud_conversions.h"
#include "exploration_mission/mission_prior.h"
#include "exploration_mission/mission_report.h"
#include "lio_bridge/local_map.h"
#include "prior_map_tools/prior_bundle.h"
#include "sketch_registration/prior_inputs.h"
#include "sketch_registration/sketch_registration.h"

namespace {

constexpr const char* kUsage =
    R"(usage: registration_replay --bag FLIGHT.bag --prior SKETCH.prior [--truth SKETCH.prior.truth.yaml]
                           [--cloud-topic T] [--odom-topic T] [--rate-hz R] [--start-s T]
                           [--verbose]

Registers the bag's scans (default /cloud_registered, /Odometry: FAST-LIO2's topics, in its
world frame) to the prior bundle's sketch, one registration frame every 1/R s of bag time
(default 0.2 Hz), with the node's default parameters, and prints one line per frame. Scans
before bag time --start-s build the map; frames due before it are dropped (as a node
started late drops them).
--truth: the true T_world_sketch (sim_prior writes it beside a simulated sketch's bundle); the
best hypothesis' placement error (RMS displacement of the sketch walls) is printed, and the exit
status is 0 only if the last frame's best hypothesis lies within 1 m of it.
--verbose: the verifier's counts per frame, and with --truth the selected candidates' distance
to the robot's true place in the sketch (d_cand = 4 d_gap decides a frame's retrieval success).
Exit status: 0 (registered; within 1 m with --truth), 1 (not), 2 bad input.
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace efs;
  try {
    const CliArgs args(argc, argv,
                       {"bag", "prior", "truth", "cloud-topic", "odom-topic", "rate-hz", "start-s"},
                       {"help", "verbose"});
    if (args.flag("help") || argc == 1) {
      std::cout << kUsage;
      return argc == 1 ? 2 : 0;
    }
    const std::string cloud_topic = args.str("cloud-topic", "/cloud_registered");
    const std::string odom_topic = args.str("odom-topic", "/Odometry");
    const prior_map::PriorBundle bundle = prior_map::loadPriorBundle(args.required("prior"));
    std::optional<Sim2> truth;
    if (args.has("truth")) truth = mission::loadTruth(args.required("truth"));
    const std::vector<Eigen::Vector2d> walls = bundle.wallPoints();

    registration::SketchRegistrationConfig config;
    const registration::RegistrationPrior inputs =
        registration::registrationPriorFromBundle(bundle, config.d_gap_m);
    registration::SketchRegistration registration(config, inputs.boundary_sketch_m,
                                                  inputs.candidates_sketch_m);
    lio::LocalMap map;
    lio::FrameDecimator frames(args.number("rate-hz", 0.2));
    const double start_s = args.number("start-s", 0.0);

    rosbag::Bag bag(args.required("bag"), rosbag::bagmode::Read);
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{cloud_topic, odom_topic}));
    std::optional<Eigen::Vector3d> robot_m;
    size_t scans = 0;
    std::optional<double> last_error_m;
    for (const rosbag::MessageInstance& m : view) {
      if (auto odom = m.instantiate<nav_msgs::Odometry>()) {
        const auto& p = odom->pose.pose.position;
        robot_m = Eigen::Vector3d(p.x, p.y, p.z);
        continue;
      }
      const auto cloud = m.instantiate<sensor_msgs::PointCloud2>();
      if (!cloud || !robot_m) continue;
      std::vector<Eigen::Vector3f> scan;
      try {
        scan = ros_common::fromPointCloud2(*cloud);
      } catch (const std::exception& e) {
        // As lio_bridge: an unreadable scan is skipped with its reason, the replay goes on.
        std::fprintf(stderr, "registration_replay: scan at %.2f s skipped: %s\n",
                     cloud->header.stamp.toSec(), e.what());
        continue;
      }
      ++scans;
      map.insert(scan, *robot_m);
      map.crop(*robot_m);
      const double t_s = cloud->header.stamp.toSec();
      if (!frames.due(t_s) || t_s < start_s) continue;
      registration::Points3d points;
      for (const auto& p : map.points()) points.emplace_back(p.cast<double>());
      const auto& result = registration.addFrame(t_s, *robot_m, points);
      std::printf("t %7.2f s  %-26s hyps %zu", t_s, registration::toString(result.status),
                  result.hypotheses.size());
      last_error_m.reset();
      if (!result.hypotheses.empty()) {
        const auto& best = result.hypotheses.front();
        std::printf("  best id %u F %.2f m scale %.3f", best.id, best.fitness_m,
                    best.T_world_sketch.scale);
        if (truth) {
          last_error_m = mission::registrationErrorRmse(best.T_world_sketch, *truth, walls);
          std::printf("  placement error %.2f m", *last_error_m);
        }
      }
      std::printf("  | %s\n", result.message.c_str());
      if (args.flag("verbose")) {
        const auto& d = result.last_frame;
        const auto& vs = d.verifier;
        std::printf(
            "           %zu candidates; pairs %zu (scale ok %zu), triplets %zu tested, %zu "
            "accepted, %zu tracks, %zu representatives, %zu ICP runs",
            d.candidates.size(), vs.anchor_pairs, vs.pairs_scale_ok, vs.triplets_tested,
            vs.triplets_accepted, vs.tracks, vs.representatives, d.icp_runs);
        if (truth && !d.candidates.empty()) {
          const Eigen::Vector2d at_sketch = truth->inverse().apply(robot_m->head<2>());
          double nearest = std::numeric_limits<double>::infinity();
          for (const auto& c : d.candidates) {
            nearest = std::min(nearest, (c.c_sketch - at_sketch).norm());
          }
          std::printf("; nearest candidate %.1f sketch m from the truth", nearest);
        }
        if (truth) {
          // Whether the fitness test would pass the truth itself on this frame.
          const registration::IcpResult e = registration.evaluateOnLastFrame(*truth);
          if (e.usable) {
            char reverse[16] = "-";
            if (e.reverse_inlier_ratio)
              std::snprintf(reverse, sizeof reverse, "%.2f", *e.reverse_inlier_ratio);
            std::printf("; truth F %.2f m, forward %.2f, reverse %s, inside %.2f", e.fitness_m,
                        e.forward_inlier_ratio, reverse, e.inside_ratio);
          }
        }
        std::printf("\n");
      }
    }
    std::printf("registration_replay: %zu scans\n", scans);
    if (truth) return last_error_m && *last_error_m <= 1.0 ? 0 : 1;
    return registration.result().hypotheses.empty() ? 1 : 0;
  } catch (const std::exception& e) {
    std::cerr << "registration_replay: " << e.what() << "\n";
    return 2;
  }
}
