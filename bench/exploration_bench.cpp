// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// exploration_bench: complete closed-loop explorations in simulated time (ExplorationMission, the
// same core classes as the nodes), several trials in parallel, compared the way the paper does
// (Sec. VII-C): per world, exploration time, flight distance and average speed (avg / std / max /
// min) and the finished count per method; registration time to convergence; the relative gain of
// the proposed method over each baseline. Writes CSV, Markdown, coverage plots and, per world,
// the first seed's flights over the ground truth and the sketch (trajectories_N.png).
//
//   exploration_bench --quick | --full  [--out results/bench] [--jobs N] [--worlds a,b]
//                     [--methods m1,m2] [--time-limit S] [--seeds N] [--progress-every S]
//                     [--planner-rate HZ]
//   --quick: small worlds (about 40 m), one seed.  --full: paper-sized worlds, 5 seeds.
//   --progress-every S: a line per running trial every S seconds of simulated time (default 100
//   with --full, where one flight can take an hour of wall time; 0, off, with --quick).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <thread>

#include "efs_common/cli_args.h"
#include "efs_common/resource_usage.h"
#include "exploration_mission/mission_report.h"
#include "exploration_mission/mission_spec.h"

namespace {

using efs::mission::MissionReport;
using efs::mission::MissionSpec;

struct Trial {
  std::string world_label;  ///< table name of the world
  MissionSpec spec;
  int seed_index = 0;
};

struct TrialResult {
  Trial trial;
  MissionReport report;
  std::vector<efs::sim::CoverageLogEntry> coverage;
  std::string error;  ///< the trial could not run (bad input)
  double wall_s = 0.0;
  cv::Mat trajectory;  ///< first seed only: the flown path over the world and the sketch
};

struct WorldEntry {
  std::string label;
  efs::sim::WorldSource source;
  std::vector<std::string> real_sketches;  ///< user drawings (ed21); empty = draw variants
  double real_sketch_scale_guess = 0.1;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

struct Stats {
  double avg = 0, stddev = 0, max = 0, min = 0;
  int n = 0;
};

Stats stats(const std::vector<double>& v) {
  Stats s;
  s.n = static_cast<int>(v.size());
  if (v.empty()) return s;
  s.max = *std::max_element(v.begin(), v.end());
  s.min = *std::min_element(v.begin(), v.end());
  for (double x : v) s.avg += x;
  s.avg /= v.size();
  for (double x : v) s.stddev += (x - s.avg) * (x - s.avg);
  s.stddev = v.size() > 1 ? std::sqrt(s.stddev / (v.size() - 1)) : 0.0;
  return s;
}

std::string fmt(double v, int d = 1) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.*f", d, v);
  return buf;
}

std::string statsCell(const Stats& s, int d = 1) {
  if (s.n == 0) return "—";
  return fmt(s.avg, d) + " / " + fmt(s.stddev, d) + " / " + fmt(s.max, d) + " / " + fmt(s.min, d);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace efs;
  try {
    const CliArgs args(argc, argv,
                       {"out", "jobs", "worlds", "methods", "time-limit", "seeds", "progress-every",
                        "planner-rate"},
                       {"quick", "full", "help"});
    if (args.flag("help") || (!args.flag("quick") && !args.flag("full"))) {
      std::cout << "usage: exploration_bench --quick | --full [--out DIR] [--jobs N] "
                   "[--worlds a,b] [--methods m1,m2] [--time-limit S] [--seeds N] "
                   "[--progress-every S] [--planner-rate HZ]\n";
      return args.flag("help") ? 0 : 2;
    }
    const bool full = args.flag("full");
    const std::string out_dir = args.str("out", "results/bench");
    const int jobs =
        static_cast<int>(args.integer("jobs", std::max(1u, std::thread::hardware_concurrency())));
    const int seeds = static_cast<int>(args.integer("seeds", full ? 5 : 1));
    const double time_limit_s = args.number("time-limit", full ? 2000.0 : 600.0);
    const double progress_every_s = args.number("progress-every", full ? 100.0 : 0.0);
    // The planner's target updates: 0 after every scan, else at this rate as the node's timer.
    const double planner_rate_hz = args.number("planner-rate", 0.0);
    if (jobs < 1) throw CliError("--jobs must be at least 1");
    if (seeds < 1) throw CliError("--seeds must be at least 1");
    if (!(time_limit_s > 0.0) || !std::isfinite(time_limit_s))
      throw CliError("--time-limit must be a positive number of seconds");
    if (!(planner_rate_hz >= 0.0) || !std::isfinite(planner_rate_hz))
      throw CliError("--planner-rate must be 0 (after every scan) or a positive rate in Hz");
    if (!(progress_every_s >= 0.0) || !std::isfinite(progress_every_s))
      throw CliError("--progress-every must be 0 (off) or a positive number of seconds");
    const std::string data_dir = [] {
      const char* env = std::getenv("EFS_SHARED_DATA_DIR");
      return std::string(env ? env : "../shared/data");
    }();

    std::vector<WorldEntry> worlds;
    for (const std::string kind : {"garage", "simple_cave", "indoor", "subt_cave"}) {
      WorldEntry w;
      w.label = kind + std::string(full ? " (paper size)" : " (small)");
      w.source.kind = kind;
      w.source.size = full ? "paper" : "small";
      worlds.push_back(w);
    }
    {
      WorldEntry w;
      w.label = "ed21 (real building, real sketches)";
      w.source.sdf_path = data_dir + "/ed21/ed21.world";
      w.source.resolution_m = 0.1;
      for (const char* s :
           {"sketch_ed21.png", "sketch_ed21_1.png", "sketch_ed21_2.png", "sketch_ed21_3.png"}) {
        w.real_sketches.push_back(data_dir + "/ed21/" + s);
      }
      worlds.push_back(w);
    }
    if (full) {
      WorldEntry w;
      w.label = "pittsburgh mine";
      w.source.sdf_path = data_dir + "/pittsburgh_mine/pittsburgh_mine.world";
      worlds.push_back(w);
    }
    if (args.has("worlds")) {
      const auto wanted = split(args.str("worlds", ""));
      std::vector<WorldEntry> kept;
      for (const auto& w : worlds) {
        for (const auto& name : wanted) {
          if (w.label.rfind(name, 0) == 0) kept.push_back(w);
        }
      }
      worlds = kept;
    }
    const std::vector<std::string> methods =
        split(args.str("methods", "proposed,prior_free,greedy_prior,nearest_frontier"));

    std::vector<Trial> trials;
    for (const auto& w : worlds) {
      for (int s = 0; s < seeds; ++s) {
        for (const auto& method : methods) {
          MissionSpec spec;
          spec.world = w.source;
          spec.world.seed = static_cast<uint64_t>(1 + s);
          spec.method = method;
          spec.sketch_seed = static_cast<uint64_t>(1 + s);
          if (!spec.usesPrior()) {
            trials.push_back({w.label, spec, s});
            continue;
          }
          if (!w.real_sketches.empty()) {
            for (const auto& path : w.real_sketches) {
              spec.sketch_path = path;
              spec.scale_guess_m_per_px = w.real_sketch_scale_guess;
              trials.push_back({w.label, spec, s});
            }
            continue;
          }
          const std::vector<std::string> variants =
              method == "proposed" ? std::vector<std::string>{"precise", "partial", "deformed"}
                                   : std::vector<std::string>{"precise"};
          for (const auto& v : variants) {
            spec.sketch_variant = v;
            trials.push_back({w.label, spec, s});
          }
        }
      }
    }

    std::filesystem::create_directories(out_dir);
    std::printf("exploration_bench (%s): %zu trials on %d thread(s), time limit %.0f s\n",
                full ? "full" : "quick", trials.size(), jobs, time_limit_s);
    std::vector<TrialResult> results(trials.size());
    std::atomic<size_t> next{0}, done{0};
    std::mutex print_mutex;
    const Stopwatch wall;
    auto worker = [&]() {
      for (size_t i = next++; i < trials.size(); i = next++) {
        TrialResult& r = results[i];
        r.trial = trials[i];
        const Stopwatch trial_wall;
        try {
          mission::MissionConfig config;
          config.time_limit_s = time_limit_s;
          config.planner_update_rate_hz = planner_rate_hz;
          config.record_map = false;  // no map is saved; keeps parallel trials small
          const auto m = mission::makeMission(r.trial.spec, config);
          const auto progress = [&](const mission::MissionProgress& p) {
            const std::string registration =
                p.registration_status.empty() ? "" : ", registration " + p.registration_status;
            std::lock_guard<std::mutex> lock(print_mutex);
            std::printf(
                "          %-40s %-28s seed %d: %5.0f s, coverage %5.1f %%, %6.0f m%s "
                "(wall %.0f s)\n",
                r.trial.world_label.c_str(), r.trial.spec.label().c_str(), r.trial.seed_index + 1,
                p.time_s, 100.0 * p.coverage, p.flight_distance_m, registration.c_str(),
                trial_wall.elapsedSeconds());
            std::fflush(stdout);
          };
          if (progress_every_s > 0.0) {
            m->run(progress, progress_every_s);
          } else {
            m->run();
          }
          r.report = mission::makeReport(*m, r.trial.world_label, r.trial.spec.label());
          r.coverage = m->log().coverage_log;
          if (r.trial.seed_index == 0) r.trajectory = mission::renderTrajectoryPanel(*m);
        } catch (const std::exception& e) {
          r.error = e.what();
        }
        r.wall_s = trial_wall.elapsedSeconds();
        std::lock_guard<std::mutex> lock(print_mutex);
        std::printf("[%3zu/%zu %5.0f s] %-40s %-28s seed %d: ", ++done, trials.size(),
                    wall.elapsedSeconds(), r.trial.world_label.c_str(),
                    r.trial.spec.label().c_str(), r.trial.seed_index + 1);
        if (!r.error.empty()) {
          std::printf("ERROR %s\n", r.error.c_str());
        } else {
          std::printf("%s, %.0f s, %.0f m, coverage %.1f %%%s (wall %.0f s)\n",
                      r.report.success ? "finished" : "FAILED", r.report.exploration_time_s,
                      r.report.flight_distance_m, 100 * r.report.coverage,
                      r.report.success ? "" : (" [" + r.report.end + "]").c_str(), r.wall_s);
        }
        std::fflush(stdout);
      }
    };
    std::vector<std::thread> pool;
    for (int j = 0; j < jobs; ++j) pool.emplace_back(worker);
    for (auto& t : pool) t.join();

    // CSV of every trial.
    std::ofstream csv(out_dir + "/exploration_trials.csv");
    csv << "world,method,seed,success,end,exploration_time_s,flight_distance_m,average_speed_mps,"
           "coverage,time_to_coverage_goal_s,registration_ttc_s,registration_error_m,"
           "unseen_up,unseen_down,unseen_sideways,"
           "wall_s,error\n";
    for (const auto& r : results) {
      csv << '"' << r.trial.world_label << "\",\"" << r.trial.spec.label() << "\","
          << r.trial.seed_index + 1 << ',' << r.report.success << ',' << r.report.end << ','
          << r.report.exploration_time_s << ',' << r.report.flight_distance_m << ','
          << r.report.average_speed_mps << ',' << r.report.coverage << ','
          << (r.report.time_to_coverage_goal_s ? fmt(*r.report.time_to_coverage_goal_s) : "") << ','
          << (r.report.registration_ttc_s ? fmt(*r.report.registration_ttc_s) : "") << ','
          << (r.report.final_registration_error_m ? fmt(*r.report.final_registration_error_m, 2)
                                                  : "")
          << ',' << r.report.unseen_up << ',' << r.report.unseen_down << ','
          << r.report.unseen_sideways << ',' << fmt(r.wall_s) << ",\"" << r.error << "\"\n";
    }

    // One table per world, as the paper's.
    std::ostringstream md;
    md << "# Exploration benchmark (" << (full ? "full" : "quick") << ")\n\n"
       << "Protocol: v_max 4 m/s, time limit " << fmt(time_limit_s, 0)
       << " s simulated, a trial fails below 95 % coverage or on collision; the planner updates "
       << (planner_rate_hz > 0.0
               ? "at " + fmt(planner_rate_hz, 1) + " Hz"
               : std::string("after every scan (10 Hz, as the node's plan_rate_hz)"))
       << "; " << seeds
       << " seed(s). Columns: avg / std / max / min over finished trials. Gain = how much "
          "lower the proposed method's (precise sketch) average is than the baseline's. "
          "Exploration time ends when the planner has no viewpoint left (the paper's "
          "termination); '95 % at' is when the ground-truth coverage reached 95 %.\n\n";
    std::ofstream summary_csv(out_dir + "/exploration_summary.csv");
    summary_csv << "world,method,finished,trials,time_avg,time_std,time_max,time_min,dist_avg,"
                   "dist_std,dist_max,dist_min,speed_avg,ttc_avg,t95_avg\n";
    std::map<std::string, std::vector<const TrialResult*>> by_world;
    std::vector<std::string> world_order;
    for (const auto& r : results) {
      if (!by_world.count(r.trial.world_label)) world_order.push_back(r.trial.world_label);
      by_world[r.trial.world_label].push_back(&r);
    }
    for (size_t wi = 0; wi < world_order.size(); ++wi) {
      const std::string& world = world_order[wi];
      const std::string plot_name = "coverage_" + std::to_string(wi) + ".png";
      const auto& rs = by_world[world];
      md << "## " << world << "\n\n"
         << "| method | finished | exploration time [s] | flight distance [m] | avg speed [m/s] "
            "| 95 % at [s] | registration TTC [s] |\n|---|---|---|---|---|---|---|\n";
      std::vector<std::string> labels;
      for (const auto* r : rs) {
        if (std::find(labels.begin(), labels.end(), r->trial.spec.label()) == labels.end()) {
          labels.push_back(r->trial.spec.label());
        }
      }
      std::map<std::string, Stats> time_stats, dist_stats, t95_stats;
      for (const auto& label : labels) {
        std::vector<double> times, dists, speeds, ttcs, t95s;
        int finished = 0, total = 0;
        for (const auto* r : rs) {
          if (r->trial.spec.label() != label) continue;
          ++total;
          if (!r->error.empty() || !r->report.success) continue;
          ++finished;
          times.push_back(r->report.exploration_time_s);
          dists.push_back(r->report.flight_distance_m);
          speeds.push_back(r->report.average_speed_mps);
          if (r->report.registration_ttc_s) ttcs.push_back(*r->report.registration_ttc_s);
          if (r->report.time_to_coverage_goal_s) t95s.push_back(*r->report.time_to_coverage_goal_s);
        }
        const Stats t = stats(times), d = stats(dists), v = stats(speeds), c = stats(ttcs),
                    t95 = stats(t95s);
        time_stats[label] = t;
        dist_stats[label] = d;
        t95_stats[label] = t95;
        md << "| " << label << " | " << finished << "/" << total << " | " << statsCell(t) << " | "
           << statsCell(d) << " | " << (v.n ? fmt(v.avg, 2) : "—") << " | "
           << (t95.n ? fmt(t95.avg) : "—") << " | " << (c.n ? fmt(c.avg) : "—") << " |\n";
        summary_csv << '"' << world << "\",\"" << label << "\"," << finished << ',' << total << ','
                    << t.avg << ',' << t.stddev << ',' << t.max << ',' << t.min << ',' << d.avg
                    << ',' << d.stddev << ',' << d.max << ',' << d.min << ',' << v.avg << ','
                    << c.avg << ',' << t95.avg << '\n';
      }
      // Relative gains of the proposed method over each baseline.
      std::string proposed_label;
      for (const auto& label : labels) {
        if (label.rfind("proposed", 0) == 0 && time_stats[label].n > 0) {
          proposed_label = label;
          if (label.find("precise") != std::string::npos) break;
        }
      }
      if (!proposed_label.empty()) {
        md << "\nGain of **" << proposed_label << "**: ";
        bool first = true;
        for (const auto& label : labels) {
          if (label.rfind("proposed", 0) == 0 || time_stats[label].n == 0) continue;
          const double gt = 1.0 - time_stats[proposed_label].avg / time_stats[label].avg;
          const double gd = 1.0 - dist_stats[proposed_label].avg / dist_stats[label].avg;
          md << (first ? "" : "; ") << "vs " << label << " time " << fmt(100 * gt)
             << " %, distance " << fmt(100 * gd) << " %";
          if (t95_stats[proposed_label].n > 0 && t95_stats[label].n > 0)
            md << ", time to 95 % "
               << fmt(100 * (1.0 - t95_stats[proposed_label].avg / t95_stats[label].avg)) << " %";
          first = false;
        }
        md << ".\n";
      }
      md << "\n![coverage](" << plot_name << ")\n\n";
      std::vector<mission::CoverageSeries> series;
      for (const auto* r : rs) series.push_back({r->trial.spec.label(), r->coverage});
      cv::imwrite(out_dir + "/" + plot_name,
                  mission::renderCoveragePlot(series, "coverage over time: " + world));

      std::vector<mission::LabelledPanel> panels;
      for (const auto* r : rs) {
        if (r->trajectory.empty()) continue;
        panels.push_back({r->trial.spec.label() +
                              ", seed 1: " + (r->report.success ? "finished" : "not finished") +
                              " in " + fmt(r->report.exploration_time_s) + " s, " +
                              fmt(r->report.flight_distance_m, 0) + " m",
                          r->trajectory});
      }
      if (!panels.empty()) {
        const std::string name = "trajectories_" + std::to_string(wi) + ".png";
        cv::imwrite(out_dir + "/" + name, mission::stackLabelledPanels(panels, 400));
        md << "![trajectories of seed 1, red at the start to blue at the end](" << name << ")\n\n";
      }
    }
    md << "Wall time " << fmt(wall.elapsedSeconds(), 0) << " s on " << jobs << " thread(s).\n";
    std::ofstream(out_dir + "/exploration.md") << md.str();
    std::cout << "\n" << md.str();
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "exploration_bench: " << e.what() << "\n";
    return 2;
  }
}
