// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/mission_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "marsim_worlds/world_sketch.h"

namespace efs::mission {
namespace {

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

std::string jsonOptional(const std::optional<double>& v) { return v ? jsonNumber(*v) : "null"; }

std::string fmt(double v, int decimals) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

std::string fmtOptional(const std::optional<double>& v, int decimals, const std::string& unit) {
  return v ? fmt(*v, decimals) + unit : "—";
}

void writeImage(const std::string& path, const cv::Mat& image) {
  if (!cv::imwrite(path, image)) throw std::runtime_error("cannot write image '" + path + "'");
}

/// Map of the world seen from above with the flown path, red (start) to blue (end).
void drawPath(cv::Mat& img, const std::vector<cv::Point2d>& px) {
  for (size_t i = 1; i < px.size(); ++i) {
    const double f = static_cast<double>(i) / static_cast<double>(px.size());
    cv::line(img, px[i - 1], px[i], cv::Scalar(255 * f, 40, 255 * (1 - f)), 2, cv::LINE_AA);
  }
  if (!px.empty()) cv::circle(img, px.front(), 5, cv::Scalar(0, 160, 0), -1);
}

void label(cv::Mat& img, const std::string& text, int row) {
  cv::putText(img, text, cv::Point(8, 20 + 20 * row), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

/// The top-down views' scale: about 900 px across the world, no finer than 5 cm.
double trajectoryMetresPerPixel(const sim::VoxelWorld& world) {
  const Eigen::AlignedBox3d grid = world.gridBox();
  return std::max(0.05, std::max(grid.sizes().x(), grid.sizes().y()) / 900.0);
}

cv::Mat fitHeight(const cv::Mat& img, int height) {
  cv::Mat out;
  const double s = static_cast<double>(height) / img.rows;
  cv::resize(img, out, cv::Size(std::max(1, static_cast<int>(img.cols * s)), height), 0, 0,
             cv::INTER_AREA);
  return out;
}

/// The flown path in the pixels of sim::renderTopDown(world, mpp).
std::vector<cv::Point2d> pathPixels(const sim::VoxelWorld& world, const MissionLog& log,
                                    double mpp) {
  std::vector<cv::Point2d> px;
  for (const auto& rec : log.trajectory)
    px.push_back(sim::topDownPixel(world, mpp, rec.position_world_m.head<2>()));
  return px;
}

/// The world from above with its unseen surface painted over it: up-facing (floors, roofs) red,
/// down-facing (ceilings) blue, sideways orange, upward last so that an unseen floor under an
/// unseen ceiling shows; the flown path on top.
cv::Mat renderCoverageGaps(const sim::VoxelWorld& world, const MissionLog& log, double mpp) {
  cv::Mat img = sim::renderTopDown(world, mpp);
  const sim::CoverageGaps& gaps = log.coverage_gaps;
  const double voxel_m = gaps.voxel_size_m;
  const auto paint = [&](sim::SurfaceFacing facing, const cv::Scalar& colour) {
    for (size_t i = 0; i < gaps.unseen.size(); ++i) {
      if (gaps.facing[i] != facing) continue;
      const Eigen::Vector3d c = voxelCenter(gaps.unseen[i], voxel_m);
      const Eigen::Vector2d half(0.5 * voxel_m, 0.5 * voxel_m);
      const cv::Point2d lo = sim::topDownPixel(world, mpp, c.head<2>() - half);
      const cv::Point2d hi = sim::topDownPixel(world, mpp, c.head<2>() + half);
      cv::rectangle(img, lo, hi, colour, cv::FILLED);
    }
  };
  paint(sim::SurfaceFacing::kSideways, cv::Scalar(0, 150, 255));
  paint(sim::SurfaceFacing::kDown, cv::Scalar(230, 120, 30));
  paint(sim::SurfaceFacing::kUp, cv::Scalar(40, 40, 220));
  drawPath(img, pathPixels(world, log, mpp));
  label(img, "surface never seen: red facing up, blue down, orange sideways", 0);
  return img;
}

}  // namespace

double registrationErrorRmse(const Sim2& estimate, const Sim2& truth,
                             const std::vector<Eigen::Vector2d>& points) {
  if (points.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& p : points) sum += (estimate.apply(p) - truth.apply(p)).squaredNorm();
  return std::sqrt(sum / static_cast<double>(points.size()));
}

MissionReport makeReport(const ExplorationMission& mission, const std::string& world,
                         const std::string& method, const ReportConfig& config) {
  const MissionLog& log = mission.log();
  MissionReport r;
  r.world = world;
  r.method = method;
  r.end = toString(log.end);
  r.end_message = log.end_message;
  r.exploration_time_s = log.end_time_s;
  r.flight_distance_m = log.flight_distance_m;
  r.average_speed_mps = log.end_time_s > 0.0 ? log.flight_distance_m / log.end_time_s : 0.0;
  r.coverage = log.coverage;
  r.time_to_coverage_goal_s = log.time_to_coverage_goal_s;
  const sim::SimulationSession& session = mission.session();
  if (const auto* coverage = session.simulator().coverage()) {
    r.coverage_truth_voxels = coverage->totalVoxels();
  }
  r.coverage_samples_reachable = session.coverageSamplesReachable();
  r.coverage_samples_free = session.coverageSamplesTotal();
  r.success = log.end != MissionEnd::kCollision && log.coverage >= config.coverage_goal;
  r.replans = log.replans;
  r.emergency_stops = log.emergency_stops;
  r.planner_cycles = log.planner_cycles;
  // Those that were still the planner's current goal (set aside or counted as reached).
  r.goals_given_up = static_cast<size_t>(
      std::count_if(log.goal_failures.begin(), log.goal_failures.end(),
                    [](const auto& f) { return f.outcome != planner::GoalRefusal::kNotCurrent; }));
  r.viewpoints_given_up = mission.explorationManager().inputStats().viewpoints_given_up;
  r.max_tracking_error_m = log.max_tracking_error_m;
  r.rms_tracking_error_m = log.rms_tracking_error_m;
  r.min_clearance_m = log.min_clearance_m;
  r.registration_cpu_s = log.registration_cpu_s;
  r.planner_cpu_s = log.planner_cpu_s;
  r.trajectory_cpu_s = log.trajectory_cpu_s;
  r.simulator_cpu_s = log.simulator_cpu_s;
  r.unseen_up = log.coverage_gaps.up;
  r.unseen_down = log.coverage_gaps.down;
  r.unseen_sideways = log.coverage_gaps.sideways;
  r.truth_up = log.coverage_gaps.total_up;
  r.truth_down = log.coverage_gaps.total_down;
  r.truth_sideways = log.coverage_gaps.total_sideways;
  constexpr double kMb = 1024.0 * 1024.0;
  const planner::ExplorationManager& exploration = mission.explorationManager();
  r.planner_memory_mb =
      (exploration.observationMap().memoryBytes() + exploration.occupancy().memoryBytes()) / kMb;
  r.local_grid_memory_mb = mission.trajectoryServer().grid().memoryBytes() / kMb;
  r.registration_frames = log.registrations.size();
  const auto& prior = mission.prior();
  if (!prior) return r;
  r.sketch = prior->description;
  for (const auto& rec : log.registrations) {
    if (!rec.hypotheses.empty()) {
      r.first_hypothesis_s = rec.time_s;
      break;
    }
  }
  if (!prior->T_world_sketch_truth) return r;
  const Sim2& truth = *prior->T_world_sketch_truth;
  const std::vector<Eigen::Vector2d> walls = prior->bundle.wallPoints();
  // TTC: the start of the final run of frames whose best hypothesis is correct.
  std::optional<double> ttc;
  for (const auto& rec : log.registrations) {
    const bool correct =
        !rec.hypotheses.empty() && registrationErrorRmse(rec.hypotheses.front().T_world_sketch,
                                                         truth, walls) <= config.converged_error_m;
    if (!correct) {
      ttc.reset();
    } else if (!ttc) {
      ttc = rec.time_s;
    }
  }
  r.registration_ttc_s = ttc;
  for (auto it = log.registrations.rbegin(); it != log.registrations.rend(); ++it) {
    if (it->hypotheses.empty()) continue;
    const Sim2& best = it->hypotheses.front().T_world_sketch;
    r.final_registration_error_m = registrationErrorRmse(best, truth, walls);
    r.final_scale_ratio = best.scale / truth.scale;
    break;
  }
  return r;
}

std::string toJson(const MissionReport& r) {
  std::ostringstream o;
  o << "{\n"
    << "  \"world\": " << jsonString(r.world) << ",\n"
    << "  \"method\": " << jsonString(r.method) << ",\n"
    << "  \"sketch\": " << jsonString(r.sketch) << ",\n"
    << "  \"end\": " << jsonString(r.end) << ",\n"
    << "  \"end_message\": " << jsonString(r.end_message) << ",\n"
    << "  \"success\": " << (r.success ? "true" : "false") << ",\n"
    << "  \"exploration_time_s\": " << jsonNumber(r.exploration_time_s) << ",\n"
    << "  \"flight_distance_m\": " << jsonNumber(r.flight_distance_m) << ",\n"
    << "  \"average_speed_mps\": " << jsonNumber(r.average_speed_mps) << ",\n"
    << "  \"coverage\": " << jsonNumber(r.coverage) << ",\n"
    << "  \"time_to_coverage_goal_s\": " << jsonOptional(r.time_to_coverage_goal_s) << ",\n"
    << "  \"coverage_truth\": {\"voxels\": " << r.coverage_truth_voxels
    << ", \"samples_reachable\": " << r.coverage_samples_reachable
    << ", \"samples_free\": " << r.coverage_samples_free << "},\n"
    << "  \"unseen_surface\": {\"up\": " << r.unseen_up << ", \"down\": " << r.unseen_down
    << ", \"sideways\": " << r.unseen_sideways << ", \"up_of\": " << r.truth_up
    << ", \"down_of\": " << r.truth_down << ", \"sideways_of\": " << r.truth_sideways << "},\n"
    << "  \"registration_frames\": " << r.registration_frames << ",\n"
    << "  \"first_hypothesis_s\": " << jsonOptional(r.first_hypothesis_s) << ",\n"
    << "  \"registration_ttc_s\": " << jsonOptional(r.registration_ttc_s) << ",\n"
    << "  \"final_registration_error_m\": " << jsonOptional(r.final_registration_error_m) << ",\n"
    << "  \"final_scale_ratio\": " << jsonOptional(r.final_scale_ratio) << ",\n"
    << "  \"replans\": " << r.replans << ",\n"
    << "  \"emergency_stops\": " << r.emergency_stops << ",\n"
    << "  \"planner_cycles\": " << r.planner_cycles << ",\n"
    << "  \"goals_given_up\": " << r.goals_given_up << ",\n"
    << "  \"viewpoints_given_up\": " << r.viewpoints_given_up << ",\n"
    << "  \"tracking_error_m\": {\"max\": " << jsonNumber(r.max_tracking_error_m)
    << ", \"rms\": " << jsonNumber(r.rms_tracking_error_m) << "},\n"
    << "  \"min_clearance_m\": " << jsonNumber(r.min_clearance_m) << ",\n"
    << "  \"cpu_s\": {\"registration\": " << jsonNumber(r.registration_cpu_s)
    << ", \"planner\": " << jsonNumber(r.planner_cpu_s)
    << ", \"trajectory\": " << jsonNumber(r.trajectory_cpu_s)
    << ", \"simulator\": " << jsonNumber(r.simulator_cpu_s) << "},\n"
    << "  \"memory_mb\": {\"planner\": " << jsonNumber(r.planner_memory_mb)
    << ", \"local_grid\": " << jsonNumber(r.local_grid_memory_mb) << "}\n"
    << "}\n";
  return o.str();
}

std::string toMarkdown(const MissionReport& r) {
  std::ostringstream o;
  o << "| | |\n|---|---|\n"
    << "| world | " << r.world << " |\n"
    << "| method | `" << r.method << "` |\n"
    << "| sketch | " << (r.sketch.empty() ? "none" : r.sketch) << " |\n"
    << "| outcome | " << (r.success ? "**success**" : "**failed**") << ": " << r.end
    << (r.end_message.empty() ? "" : " (" + r.end_message + ")") << " |\n"
    << "| exploration time | " << fmt(r.exploration_time_s, 1) << " s |\n"
    << "| flight distance | " << fmt(r.flight_distance_m, 1) << " m |\n"
    << "| average speed | " << fmt(r.average_speed_mps, 2) << " m/s |\n"
    << "| coverage | " << fmt(100.0 * r.coverage, 1) << " % (95 % reached at "
    << fmtOptional(r.time_to_coverage_goal_s, 1, " s") << ") |\n"
    << "| coverage counts | " << r.coverage_truth_voxels << " surface voxels, seen from "
    << r.coverage_samples_reachable << " of " << r.coverage_samples_free
    << " free-space samples (those the start can reach) |\n"
    << "| surface never seen: facing up / down / sideways | " << r.unseen_up << " of " << r.truth_up
    << " / " << r.unseen_down << " of " << r.truth_down << " / " << r.unseen_sideways << " of "
    << r.truth_sideways << " voxels (coverage_gaps.png) |\n";
  if (!r.sketch.empty()) {
    o << "| registration frames | " << r.registration_frames << " |\n"
      << "| first hypothesis | " << fmtOptional(r.first_hypothesis_s, 1, " s") << " |\n"
      << "| registration time to convergence | " << fmtOptional(r.registration_ttc_s, 1, " s")
      << " |\n"
      << "| registration error (RMSE of sketch walls) | "
      << fmtOptional(r.final_registration_error_m, 2, " m") << " |\n"
      << "| estimated / true scale | " << fmtOptional(r.final_scale_ratio, 3, "") << " |\n";
  }
  o << "| replans / emergency stops / planner cycles | " << r.replans << " / " << r.emergency_stops
    << " / " << r.planner_cycles << " |\n"
    << "| goals the local planner gave up on | " << r.goals_given_up << " |\n"
    << "| viewpoints left unvisited, given up as unreachable | " << r.viewpoints_given_up << " |\n"
    << "| tracking error max / RMS | " << fmt(r.max_tracking_error_m, 2) << " / "
    << fmt(r.rms_tracking_error_m, 2) << " m |\n"
    << "| closest approach to the world (centre; collision radius 0.25 m) | "
    << fmt(r.min_clearance_m, 2) << " m |\n"
    << "| CPU: registration / planner / trajectory / simulator | " << fmt(r.registration_cpu_s, 1)
    << " / " << fmt(r.planner_cpu_s, 1) << " / " << fmt(r.trajectory_cpu_s, 1) << " / "
    << fmt(r.simulator_cpu_s, 1) << " s |\n"
    << "| memory at the end: exploration maps / local grid | " << fmt(r.planner_memory_mb, 1)
    << " / " << fmt(r.local_grid_memory_mb, 1) << " MB |\n";
  return o.str();
}

cv::Mat renderTrajectoryPanel(const ExplorationMission& mission) {
  const MissionLog& log = mission.log();
  const sim::VoxelWorld& world = mission.session().world();
  const double mpp = trajectoryMetresPerPixel(world);
  cv::Mat truth = sim::renderTopDown(world, mpp);
  drawPath(truth, pathPixels(world, log, mpp));
  label(truth, "ground truth (top-down)", 0);
  cv::Mat panel = truth;
  const auto& prior = mission.prior();
  const auto* result = mission.registrationResult();
  if (prior && !prior->sketch_image.empty()) {
    cv::Mat sketch;
    if (prior->sketch_image.channels() == 1) {
      cv::cvtColor(prior->sketch_image, sketch, cv::COLOR_GRAY2BGR);
    } else {
      sketch = prior->sketch_image.clone();
    }
    if (result && !result->hypotheses.empty()) {
      const Sim2 T_sketch_world = result->hypotheses.front().T_world_sketch.inverse();
      const prior_map::SketchFrame& frame = prior->bundle.frame;
      std::vector<cv::Point2d> spx;
      for (const auto& rec : log.trajectory) {
        const Eigen::Vector2d uv =
            frame.toPixel(T_sketch_world.apply(rec.position_world_m.head<2>()));
        spx.emplace_back(uv.x(), uv.y());
      }
      drawPath(sketch, spx);
      label(sketch, "sketch, path mapped by the best hypothesis", 0);
    } else {
      label(sketch, "sketch (no registration hypothesis)", 0);
    }
    const int h = std::max(truth.rows, 400);
    cv::hconcat(fitHeight(truth, h), fitHeight(sketch, h), panel);
  }
  return panel;
}

cv::Mat stackLabelledPanels(const std::vector<LabelledPanel>& panels, int row_height_px) {
  if (row_height_px < 1) {
    throw std::invalid_argument("stackLabelledPanels: row height must be positive");
  }
  if (panels.empty()) return cv::Mat();
  constexpr int kBanner = 28;  // px above each panel for its caption
  std::vector<cv::Mat> scaled;
  int width_px = 1;
  for (const LabelledPanel& p : panels) {
    if (p.image.empty() || p.image.type() != CV_8UC3) {
      throw std::invalid_argument("stackLabelledPanels: panel '" + p.label +
                                  "' is not a non-empty BGR image");
    }
    scaled.push_back(fitHeight(p.image, row_height_px));
    width_px = std::max(width_px, scaled.back().cols);
  }
  cv::Mat out(static_cast<int>(panels.size()) * (kBanner + row_height_px), width_px, CV_8UC3,
              cv::Scalar(255, 255, 255));
  for (size_t k = 0; k < panels.size(); ++k) {
    const int top = static_cast<int>(k) * (kBanner + row_height_px);
    out.rowRange(top, top + kBanner).setTo(cv::Scalar(235, 235, 235));
    cv::putText(out, panels[k].label, cv::Point(8, top + 19), cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    scaled[k].copyTo(out(cv::Rect(0, top + kBanner, scaled[k].cols, row_height_px)));
  }
  return out;
}

std::vector<std::string> writeMissionPlots(const ExplorationMission& mission,
                                           const std::string& dir) {
  std::vector<std::string> written;
  const MissionLog& log = mission.log();
  written.push_back(dir + "/trajectory.png");
  writeImage(written.back(), renderTrajectoryPanel(mission));
  const sim::VoxelWorld& world = mission.session().world();
  written.push_back(dir + "/coverage_gaps.png");
  writeImage(written.back(), renderCoverageGaps(world, log, trajectoryMetresPerPixel(world)));

  written.push_back(dir + "/coverage.png");
  writeImage(written.back(),
             renderCoveragePlot({{mission.session().world().name, log.coverage_log}},
                                "coverage over simulated time"));
  return written;
}

cv::Mat renderCoveragePlot(const std::vector<CoverageSeries>& series, const std::string& title) {
  const int W = 900, H = 450, L = 60, B = 40, T = 30, R = 230;
  cv::Mat plot(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double t_max = 1.0;
  for (const auto& s : series) {
    if (!s.log.empty()) t_max = std::max(t_max, s.log.back().stamp_s);
  }
  auto px = [&](double t, double c) {
    return cv::Point2d(L + (W - L - R) * t / t_max, H - B - (H - B - T) * c);
  };
  cv::rectangle(plot, px(0, 0), px(t_max, 1), cv::Scalar(0, 0, 0), 1);
  for (int i = 1; i < 10; ++i) {
    cv::line(plot, px(0, i / 10.0), px(t_max, i / 10.0), cv::Scalar(225, 225, 225), 1);
  }
  cv::line(plot, px(0, 0.95), px(t_max, 0.95), cv::Scalar(0, 160, 0), 1);
  for (int i = 0; i <= 4; ++i) {
    cv::putText(plot, fmt(t_max * i / 4, 0) + " s", px(t_max * i / 4, 0) + cv::Point2d(-15, 20),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    cv::putText(plot, fmt(25 * i, 0) + " %", px(0, i / 4.0) + cv::Point2d(-50, 5),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  const cv::Scalar palette[] = {{200, 80, 0},  {0, 0, 220},   {0, 150, 0},  {160, 0, 160},
                                {0, 140, 200}, {120, 120, 0}, {80, 80, 80}, {0, 90, 160}};
  std::vector<std::string> labels;
  for (const auto& s : series) {
    auto it = std::find(labels.begin(), labels.end(), s.label);
    if (it == labels.end()) it = labels.insert(labels.end(), s.label);
    const cv::Scalar colour = palette[(it - labels.begin()) % 8];
    for (size_t i = 1; i < s.log.size(); ++i) {
      cv::line(plot, px(s.log[i - 1].stamp_s, s.log[i - 1].coverage_fraction),
               px(s.log[i].stamp_s, s.log[i].coverage_fraction), colour, 2, cv::LINE_AA);
    }
  }
  for (size_t i = 0; i < labels.size(); ++i) {
    const cv::Point2d at(W - R + 10, T + 20 + 20 * static_cast<double>(i));
    cv::line(plot, at, at + cv::Point2d(20, 0), palette[i % 8], 3);
    cv::putText(plot, labels[i], at + cv::Point2d(26, 5), cv::FONT_HERSHEY_SIMPLEX, 0.42,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  cv::putText(plot, title, cv::Point(L, 20), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  return plot;
}

}  // namespace efs::mission
