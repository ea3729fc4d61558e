// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The written outcome of a mission (issue 7's report, issue 8's per-trial row): exploration time,
// flight distance, average speed, coverage, success, and — where the sketch's true placement is
// known (generated worlds; evaluation only) — registration time to convergence and error.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "exploration_mission/exploration_mission.h"

namespace efs::mission {

struct ReportConfig {
  /// The best hypothesis counts as correct when its registration error is at most this [m].
  double converged_error_m = 1.0;
  double coverage_goal = 0.95;
};

struct MissionReport {
  std::string world;
  std::string method;  ///< proposed, prior_free, ...
  std::string sketch;  ///< the sketch's description, empty without one
  std::string end;     ///< toString(MissionEnd)
  std::string end_message;
  bool success = false;  ///< coverage goal reached, no collision
  double exploration_time_s = 0.0;
  double flight_distance_m = 0.0;
  double average_speed_mps = 0.0;
  double coverage = 0.0;
  std::optional<double> time_to_coverage_goal_s;
  /// What coverage counts: surface voxels seen from the free-space samples the start can reach.
  size_t coverage_truth_voxels = 0;
  size_t coverage_samples_reachable = 0, coverage_samples_free = 0;
  // Registration (with a sketch); the error needs the truth.
  size_t registration_frames = 0;
  std::optional<double> first_hypothesis_s;
  std::optional<double> registration_ttc_s;  ///< from then on the best hypothesis was correct
  std::optional<double> final_registration_error_m;
  std::optional<double> final_scale_ratio;  ///< estimated / true scale of the best hypothesis
  size_t replans = 0, emergency_stops = 0, planner_cycles = 0;
  size_t goals_given_up = 0;
  size_t viewpoints_given_up = 0;  ///< set aside unreachable_attempts times (never flown to)
  double max_tracking_error_m = 0.0, rms_tracking_error_m = 0.0;
  double min_clearance_m = 0.0;  ///< closest approach of the vehicle centre to the world
  double registration_cpu_s = 0.0, planner_cpu_s = 0.0, trajectory_cpu_s = 0.0;
  double simulator_cpu_s = 0.0;
  /// Heap held at the end: the exploration planner's observation map and occupancy, and the
  /// local planner's grid with its surface memory. Both grow with the mapped surface.
  double planner_memory_mb = 0.0, local_grid_memory_mb = 0.0;
  /// Ground-truth surface never seen, by the way it faces (sim::coverageGaps).
  size_t unseen_up = 0, unseen_down = 0, unseen_sideways = 0;
  size_t truth_up = 0, truth_down = 0, truth_sideways = 0;  ///< of the whole ground truth
};

/// Root-mean-square distance between `points` mapped by `estimate` and by `truth` (the
/// registration error of the paper's tables, in the target frame's units).
double registrationErrorRmse(const Sim2& estimate, const Sim2& truth,
                             const std::vector<Eigen::Vector2d>& points);

MissionReport makeReport(const ExplorationMission& mission, const std::string& world,
                         const std::string& method, const ReportConfig& config = {});

std::string toJson(const MissionReport& report);
std::string toMarkdown(const MissionReport& report);

/// One curve of a coverage plot.
struct CoverageSeries {
  std::string label;
  std::vector<sim::CoverageLogEntry> log;
};
/// Coverage over simulated time, one colour per distinct label (same label = same colour), the
/// 95 % line, axes and a legend. CV_8UC3.
cv::Mat renderCoveragePlot(const std::vector<CoverageSeries>& series, const std::string& title);

/// trajectory.png's picture: the ground truth from above with the flown path (red at the start
/// to blue at the end) and, with a sketch, the sketch with the path mapped into it by the final
/// best hypothesis, side by side. CV_8UC3.
cv::Mat renderTrajectoryPanel(const ExplorationMission& mission);

/// A picture under a one-line caption.
struct LabelledPanel {
  std::string label;
  cv::Mat image;  ///< CV_8UC3
};
/// The panels one under the other, each scaled to `row_height_px` under a caption band and
/// left-aligned on white (the widest sets the width): the benchmark's view of one world's
/// flights, every one at the same scale. Throws std::invalid_argument on an empty or non-BGR
/// panel or a height below 1; no panels give an empty cv::Mat.
cv::Mat stackLabelledPanels(const std::vector<LabelledPanel>& panels, int row_height_px);

/// Writes `<dir>/trajectory.png` (ground-truth top-down view and, with a sketch, the sketch with
/// the trajectory mapped by the final best hypothesis), `<dir>/coverage.png` and
/// `<dir>/coverage_gaps.png` (the unseen ground-truth surface from above, coloured by the way it
/// faces, under the flown path). Returns the files written. Throws std::runtime_error naming a file
/// that cannot be written.
std::vector<std::string> writeMissionPlots(const ExplorationMission& mission,
                                           const std::string& dir);

}  // namespace efs::mission
