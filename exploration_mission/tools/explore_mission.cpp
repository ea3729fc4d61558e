// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// explore_mission: one closed-loop exploration in simulated time, in-process, with the same core
// classes as the ROS graph; writes a report (JSON + Markdown) and pictures.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "efs_common/cli_args.h"
#include "efs_common/resource_usage.h"
#include "exploration_mission/goal_failure_log.h"
#include "exploration_mission/mission_report.h"
#include "exploration_mission/mission_spec.h"
#include "exploration_mission/plan_log.h"
#include "exploration_mission/registration_log.h"

namespace {

constexpr const char* kUsage =
    R"(usage: explore_mission [options] --out DIR

Flies one headless closed-loop exploration in simulated time and writes DIR/summary.json,
DIR/summary.md, DIR/trajectory.png, DIR/coverage.png, DIR/coverage_gaps.png (the surface never
seen, from above), DIR/plan_log.csv (a line per planning cycle: mode, hypothesis, guidepoint
states, next guidepoint, goal), DIR/goal_failures.csv (a line per goal the local planner gave up
on: where, why, what the planner made of it), and with a sketch DIR/prior.prior (the
pre-processed sketch), DIR/prior_overlay.png (and DIR/sketch.png when it draws one) and
DIR/registration_log.csv (a line per registration frame: status, its reason, best hypothesis),
and what the mission leaves behind in DIR/map/: cloud.pcd (dense point cloud), occupancy.bt
(OctoMap), trajectory.csv and registration.yaml (the sketch-to-world transforms), world frame.
Exit status: 0 success, 3 finished without success (coverage < 95 % or collision), 2 bad input.

World (generated unless a file is given):
  --world KIND          garage | simple_cave | subt_cave | indoor    (default simple_cave)
  --size SIZE           small | paper                               (default small)
  --seed N              world seed                                  (default 1)
  --resolution M        world voxel size                            (default 0.15)
  --sdf/--mesh/--pcd F  import a real world instead
  --start-index N       which start pose of the world               (default 0)
Sketch:
  --variant V           draw the world's sketch: precise | partial | deformed | scaled (default deformed)
  --sketch-seed N       seed of the drawing                         (default 1)
  --sketch FILE         a user's drawing instead (needs --scale-guess; no ground truth)
  --scale-guess M       metres per pixel the user believes (default: the drawing's stated scale)
  --mapping-range M     guidepoint spacing base, paper Sec. IV-B    (default 5)
Method and limits:
  --method M            proposed | prior_free | greedy_prior | nearest_frontier (default proposed)
  --time-limit S        simulated seconds                           (default 600)
  --progress S          progress line every S simulated seconds     (default 10)
Fault injection:
  --planner-scan-latency S  scans reach the planner S s late         (default 0)
  --planner-rate HZ     target updates per second (default 0: every scan)
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace efs;
  try {
    std::set<std::string> options = mission::missionSpecOptions();
    options.insert(
        {"start-index", "time-limit", "progress", "planner-scan-latency", "planner-rate", "out"});
    const CliArgs args(argc, argv, options, {"help"});
    if (args.flag("help")) {
      std::cout << kUsage;
      return 0;
    }
    const std::string out_dir = args.required("out");
    const mission::MissionSpec spec = mission::missionSpecFromArgs(args);
    mission::MissionConfig config;
    config.session.start_index = static_cast<int>(args.integer("start-index", 0));
    config.time_limit_s = args.number("time-limit", 600.0);
    config.planner_scan_latency_s = args.number("planner-scan-latency", 0.0);
    config.planner_update_rate_hz = args.number("planner-rate", 0.0);
    std::filesystem::create_directories(out_dir);

    const Stopwatch wall;
    std::cout << "[explore_mission] " << spec.label() << " in " << spec.world.describe() << "\n";
    const auto mission = mission::makeMission(spec, config, out_dir + "/sketch.png");
    if (mission->prior()) {
      // The pre-processed sketch, for a person (overlay) and for a ROS replay (bundle).
      const prior_map::PriorBundle& bundle = mission->prior()->bundle;
      prior_map::savePriorBundle(bundle, out_dir + "/prior.prior");
      cv::imwrite(out_dir + "/prior_overlay.png", prior_map::renderOverlay(bundle));
      std::cout << "[explore_mission] sketch: " << mission->prior()->description << ", "
                << bundle.guidepoints.size() << " guidepoints\n";
    }
    // Why the flight went where it went: one line per planning cycle.
    std::ofstream plan_csv(out_dir + "/plan_log.csv");
    mission::PlanLog plan_log(plan_csv);
    mission->setPlanObserver(
        [&plan_log](double t, const Eigen::Vector3d& robot, const planner::ExplorationManager& m) {
          plan_log.record(t, robot, m);
        });
    mission->run(
        [](const mission::MissionProgress& p) {
          std::printf(
              "[%6.0f s] coverage %5.1f %%  distance %7.1f m  hypotheses %zu (best %.2f, %s)  "
              "planner %s\n",
              p.time_s, 100.0 * p.coverage, p.flight_distance_m, p.hypotheses, p.best_confidence,
              p.registration_status.empty() ? "no sketch" : p.registration_status.c_str(),
              p.planner_state.c_str());
          std::fflush(stdout);
        },
        args.number("progress", 10.0));

    const mission::MissionReport report =
        mission::makeReport(*mission, spec.world.describe(), spec.label());
    std::ofstream(out_dir + "/summary.json") << mission::toJson(report);
    if (mission->prior()) {
      std::ofstream registration_csv(out_dir + "/registration_log.csv");
      mission::writeRegistrationLog(registration_csv, mission->log().registrations);
    }
    std::ofstream goal_failures_csv(out_dir + "/goal_failures.csv");
    mission::writeGoalFailureLog(goal_failures_csv, mission->log().goal_failures);
    char wall_line[64];
    std::snprintf(wall_line, sizeof(wall_line), "\nWall time: %.0f s\n", wall.elapsedSeconds());
    const std::string md =
        "# explore_from_sketch mission report\n\n" + mission::toMarkdown(report) + wall_line;
    std::ofstream(out_dir + "/summary.md") << md;
    mission::writeMissionPlots(*mission, out_dir);
    const planner::SavedMissionMap map = mission->saveMap(out_dir + "/map");
    std::cout << "\n" << md;
    std::printf("\nMap: %s (%zu points), %s (%zu occupied, %zu free cells), %s, %s\n",
                map.cloud_pcd.c_str(), map.cloud_points, map.occupancy_bt.c_str(),
                map.occupied_cells, map.free_cells, map.trajectory_csv.c_str(),
                map.registration_yaml.c_str());
    return report.success ? 0 : 3;
  } catch (const std::exception& e) {
    std::cerr << "explore_mission: " << e.what() << "\n";
    return 2;
  }
}
