// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// registration_eval: the paper's registration tables (Sec. VII-B) measured on simulated flights.
//
// A world (generated or imported) is flown along one fixed route: the PRM of the world's own
// precise sketch, mapped into the world through that sketch's sidecar, toured greedily from the
// world's start pose at --speed m/s. A Mid-360 is cast against the world every --scan-period s
// into a lio_bridge LocalMap, and every --frame-period s of simulated time (0.2 Hz) the local map
// and robot position go to SketchRegistration::addFrame. Each trial registers a freshly drawn
// sketch variant (seed = --sketch-seed + trial) with its sidecar ground truth, or a real sketch
// (--sketch, e.g. ed21's hand drawings) whose true transform is unknown.
//
// Printed (Markdown):
//   1. single-frame retrieval: a frame succeeds if any selected candidate lies within
//      d_cand = 4 d_gap of the truth, at eta = 10 / 5 / 2.5 %; mean S_cos, S_fft, S_cv and the
//      combined S of the best-ranked correct candidate;
//   2. overall registration per trial: TTC (simulated time of the first frame whose best
//      hypothesis is a success), error (RMSE of closest point pairs between the sketch walls mapped
//      by the best hypothesis and by the truth, world metres) at the end of the flight, success;
//   3. ranking ablation: ranking score 1 - rank / N of the best-ranked correct candidate among
//      all N candidates, combined similarity vs cosine only.
// With a real sketch (no truth) a hypothesis is a success if it lays the sketch walls onto the
// world's wall columns: median distance at most --wall-median-m and at least --wall-inlier-ratio
// of the mapped wall points within 1 m (the "wall fit" columns). Single-frame and ablation tables
// need the truth and are skipped.
//
//   registration_eval [--world KIND --size small|paper --seed S | --sdf FILE]
//                     [--variant precise|partial|deformed|scaled | --sketch PNG --scale-guess M]
//                     [--trials N] [--sketch-seed S] [--max-time-s T] [--markdown FILE]
//                     [--require-success K] [--no-single-frame]
// --require-success K: exit 1 unless at least K trials succeed (smoke tests).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <queue>
#include <sstream>
#include <string>
#include <vector>

#include "efs_common/cli_args.h"
#include "efs_common/config_check.h"
#include "efs_common/point_kdtree.h"
#include "efs_common/resource_usage.h"
#include "lio_bridge/local_map.h"
#include "marsim_worlds/livox_lidar.h"
#include "marsim_worlds/world_sketch.h"
#include "marsim_worlds/world_source.h"
#include "prior_map_tools/prm.h"
#include "prior_map_tools/sketch_loader.h"
#include "prior_map_tools/traversable_region.h"
#include "sketch_registration/observation.h"
#include "sketch_registration/prior_inputs.h"
#include "sketch_registration/scale_icp.h"
#include "sketch_registration/sketch_registration.h"

namespace {

using efs::Sim2;
using Eigen::Vector2d;
using Eigen::Vector3d;
namespace pm = efs::prior_map;
namespace reg = efs::registration;
namespace sim = efs::sim;

struct Options {
  sim::WorldSource world;
  std::optional<sim::SketchVariant> variant;  ///< generated sketch (with truth)
  std::string sketch_path;                    ///< or a real sketch (no truth)
  double scale_guess_m_per_px = 0.1;
  int trials = 5;
  uint64_t sketch_seed = 1;
  double max_time_s = 300.0;
  double speed_mps = 2.0;
  double frame_period_s = 5.0;
  double scan_period_s = 0.5;
  double d_gap_m = 1.0;
  double success_rmse_m = 1.0;
  double wall_median_m = 0.5;
  double wall_inlier_ratio = 0.6;
  std::string markdown_path;
  std::optional<int> require_success;
  bool single_frame = true;
  bool verbose = false;
  reg::SketchRegistration::Config registration;  ///< paper defaults; scale_guess stays 1
};

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * ts.tv_sec + 1e-6 * ts.tv_nsec;
}

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double mean(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double stddev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

std::string fmt(double v, int digits = 2) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream os;
  os.precision(digits);
  os << std::fixed << v;
  return os.str();
}

std::string pct(double fraction) {
  return std::isfinite(fraction) ? fmt(100.0 * fraction, 1) + " %" : "-";
}

/// The sketch as the registration sees it: the bundle layers it needs (walls, traversable).
struct SketchInput {
  pm::PriorBundle bundle;
  std::optional<Sim2> T_world_sketch;  ///< the sidecar truth, when known
};

SketchInput sketchInput(const pm::LoadedSketch& loaded) {
  SketchInput in;
  in.bundle.source_path = loaded.source_path;
  in.bundle.kind = loaded.kind;
  in.bundle.frame = loaded.frame;
  in.bundle.wall_mask = loaded.wall_mask;
  in.bundle.traversable = pm::extractTraversable(loaded, {}).mask;
  return in;
}

/// A generated sketch loaded the way a user's drawing is: its stated metres per pixel is the
/// scale guess, so the bundle's sketch frame is the sidecar's frame.
SketchInput generatedSketch(const sim::VoxelWorld& world, sim::SketchVariant variant,
                            uint64_t seed) {
  sim::SketchConfig sc;
  sc.seed = seed;
  const sim::Sketch sketch = sim::drawSketch(world, variant, sc);
  pm::SketchLoadConfig lc;
  lc.kind = pm::SketchKind::kLineDrawing;
  lc.scale_guess_m_per_px = sketch.metres_per_pixel;
  SketchInput in = sketchInput(
      pm::sketchFromImage(sketch.image, lc, world.name + " " + sim::sketchVariantName(variant)));
  in.T_world_sketch = sketch.T_world_sketch;
  return in;
}

// --------------------------------------------------------------------------------------------
// The route: PRM of the world's precise sketch, in the world, toured greedily.

struct Route {
  std::vector<Vector3d> waypoints_m;  ///< world frame, flight height
  double length_m = 0.0;
};

Route planRoute(const sim::VoxelWorld& world, double max_length_m) {
  const SketchInput precise = generatedSketch(world, sim::SketchVariant::kPrecise, 1);
  pm::PrmConfig pc;
  pc.node_spacing_m = 1.0;
  const pm::Prm prm = pm::buildPrm(precise.bundle.traversable, precise.bundle.frame, pc);
  const Sim2& T = *precise.T_world_sketch;
  if (world.start_poses.empty()) throw std::runtime_error("the world has no start pose");
  const Vector3d start = world.start_poses.front().position_m;
  // Each node flies at the free height nearest the start's (caves have uneven floors).
  const auto flyHeight = [&](const Vector2d& p) -> std::optional<double> {
    for (int k = 0; k <= 40; ++k) {
      for (int sign : {1, -1}) {
        const double z = start.z() + sign * 0.25 * k;
        if (z < world.bounds().min().z() || z > world.bounds().max().z()) continue;
        if (world.clearance(Vector3d(p.x(), p.y(), z), 0.6) >= 0.4) return z;
        if (k == 0) break;
      }
    }
    return std::nullopt;
  };
  std::vector<Vector3d> nodes;
  std::vector<int> index(prm.nodes_m.size(), -1);
  for (size_t i = 0; i < prm.nodes_m.size(); ++i) {
    const Vector2d p = T.apply(prm.nodes_m[i]);
    const auto z = flyHeight(p);
    if (!z) continue;
    index[i] = static_cast<int>(nodes.size());
    nodes.emplace_back(p.x(), p.y(), *z);
  }
  std::vector<std::vector<std::pair<int, double>>> adj(nodes.size());
  for (const pm::PrmEdge& e : prm.edges) {
    const int a = index[e.a], b = index[e.b];
    if (a < 0 || b < 0) continue;
    const double len = (nodes[a] - nodes[b]).norm();
    bool ok = true;
    for (double s = 0.25; s < len && ok; s += 0.25) {
      ok = world.clearance(nodes[a] + (nodes[b] - nodes[a]) * (s / len), 0.6) >= 0.25;
    }
    if (!ok) continue;
    adj[a].push_back({b, len});
    adj[b].push_back({a, len});
  }
  if (nodes.empty()) throw std::runtime_error("no flyable PRM node in the world");
  size_t edges = 0;
  for (const auto& a : adj) edges += a.size();
  std::fprintf(stderr, "route: %zu PRM nodes, %zu flyable, %zu flyable edges\n", prm.nodes_m.size(),
               nodes.size(), edges / 2);
  int current = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if ((nodes[i] - start).norm() < (nodes[current] - start).norm()) {
      current = static_cast<int>(i);
    }
  }
  Route route;
  route.waypoints_m.push_back(start);
  route.waypoints_m.push_back(nodes[current]);
  route.length_m = (route.waypoints_m[1] - start).norm();
  const double cover_m = 6.0;
  std::vector<char> covered(nodes.size(), 0);
  const auto cover = [&](const Vector3d& p) {
    for (size_t i = 0; i < nodes.size(); ++i) {
      if ((nodes[i] - p).head<2>().norm() < cover_m) covered[i] = 1;
    }
  };
  cover(nodes[current]);
  int laps = 0;
  while (route.length_m < max_length_m) {
    // Dijkstra from the current node; go to the nearest uncovered node.
    std::vector<double> dist(nodes.size(), std::numeric_limits<double>::infinity());
    std::vector<int> prev(nodes.size(), -1);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    dist[current] = 0.0;
    queue.push({0.0, current});
    std::optional<int> target;
    while (!queue.empty()) {
      const auto [d, u] = queue.top();
      queue.pop();
      if (d > dist[u]) continue;
      if (!covered[u]) {
        target = u;
        break;
      }
      for (const auto& [v, w] : adj[u]) {
        if (d + w < dist[v]) {
          dist[v] = d + w;
          prev[v] = u;
          queue.push({dist[v], v});
        }
      }
    }
    if (!target) {
      // Everything reachable is covered: a small world is toured again (from the far side) until
      // the flight time is used, as a robot that keeps mapping would.
      if (std::count(covered.begin(), covered.end(), 1) <= 1 || ++laps > 20) break;
      std::fill(covered.begin(), covered.end(), 0);
      cover(nodes[current]);
      continue;
    }
    std::vector<int> chain;
    for (int v = *target; v != current; v = prev[v]) chain.push_back(v);
    std::reverse(chain.begin(), chain.end());
    for (int v : chain) {
      const Vector3d& p = nodes[v];
      route.length_m += (p - route.waypoints_m.back()).norm();
      route.waypoints_m.push_back(p);
      cover(nodes[v]);
    }
    current = *target;
  }
  return route;
}

/// Position and heading along the route at arc length s.
std::pair<Vector3d, double> poseAt(const Route& route, double s) {
  for (size_t i = 1; i < route.waypoints_m.size(); ++i) {
    const Vector3d d = route.waypoints_m[i] - route.waypoints_m[i - 1];
    const double len = d.norm();
    if (s <= len || i + 1 == route.waypoints_m.size()) {
      const double f = len > 1e-9 ? std::clamp(s / len, 0.0, 1.0) : 0.0;
      return {route.waypoints_m[i - 1] + f * d, std::atan2(d.y(), d.x())};
    }
    s -= len;
  }
  return {route.waypoints_m.back(), 0.0};
}

// --------------------------------------------------------------------------------------------
// Metrics.

using Tree2 = efs::PointKdTree<2>;

/// On the heap: the tree's index refers to its own point storage, so it must not move.
std::unique_ptr<Tree2> treeOf(const reg::Points2d& pts) {
  return std::make_unique<Tree2>(Tree2::Points(pts.begin(), pts.end()));
}

/// RMSE of closest point pairs: sketch walls mapped by `estimate` vs by `truth` (world metres).
/// RMS of |T_est(p) - T_true(p)| over the sketch walls: the placement error itself, which a
/// shrunken or shifted estimate cannot hide among dense walls (closest pairs can).
double placementRms(const reg::Points2d& walls, const Sim2& estimate, const Sim2& truth) {
  double sum = 0.0;
  for (const Vector2d& p : walls) sum += (estimate.apply(p) - truth.apply(p)).squaredNorm();
  return walls.empty() ? std::nan("") : std::sqrt(sum / static_cast<double>(walls.size()));
}

double registrationRmse(const reg::Points2d& walls, const Sim2& estimate, const Tree2& truth_tree) {
  double sum = 0.0;
  for (const Vector2d& p : walls) sum += truth_tree.nearest(estimate.apply(p)).second;
  return walls.empty() ? std::nan("") : std::sqrt(sum / static_cast<double>(walls.size()));
}

struct WallFit {
  double median_m = std::nan("");
  double inlier_ratio = 0.0;  ///< sketch wall points within 1 m of a world wall
  double coverage = 0.0;      ///< world wall points within 1 m of a mapped sketch wall
};

/// The world's wall columns: a tree over all of them and an even sample for coverage.
struct WorldWalls {
  std::unique_ptr<Tree2> tree;
  reg::Points2d sample;
};

/// How well the sketch walls mapped by `T` and the world's walls lie on each other, both ways:
/// indoors any point is near some wall, so a wrong (e.g. shrunken) placement can pass the first
/// direction, but it leaves most world walls uncovered.
WallFit wallFit(const reg::Points2d& walls, const Sim2& T, const WorldWalls& world) {
  std::vector<double> d;
  d.reserve(walls.size());
  size_t inliers = 0;
  reg::Points2d mapped;
  mapped.reserve(walls.size());
  for (const Vector2d& p : walls) {
    mapped.push_back(T.apply(p));
    d.push_back(std::sqrt(world.tree->nearest(mapped.back()).second));
    if (d.back() <= 1.0) ++inliers;
  }
  WallFit f;
  if (walls.empty()) return f;
  f.median_m = median(d);
  f.inlier_ratio = static_cast<double>(inliers) / walls.size();
  const std::unique_ptr<Tree2> sketch_tree = treeOf(mapped);
  size_t covered = 0;
  for (const Vector2d& q : world.sample) {
    if (sketch_tree->nearest(q).second <= 1.0) ++covered;
  }
  f.coverage = world.sample.empty() ? 0.0 : static_cast<double>(covered) / world.sample.size();
  return f;
}

struct SingleFrameStats {
  std::array<int, 3> success{0, 0, 0};  ///< eta = 10, 5, 2.5 %
  int frames = 0;
  std::vector<double> s_cos, s_fft, s_cv, s_tot;
  std::vector<double> rank_combined, rank_cosine;
  int cosine_success = 0;    ///< cosine-only ranking: a correct candidate in the top 5 %
  int combined_success = 0;  ///< combined ranking: a correct candidate in the top 5 %
};
constexpr std::array<double, 3> kEtas{0.10, 0.05, 0.025};

/// Position (0-based) of the first candidate within d_cand of `truth` in a score-sorted list.
std::optional<size_t> firstCorrect(const std::vector<reg::Candidate>& ranked, const Vector2d& truth,
                                   double d_cand_m) {
  for (size_t i = 0; i < ranked.size(); ++i) {
    if ((ranked[i].c_sketch - truth).norm() <= d_cand_m) return i;
  }
  return std::nullopt;
}

void singleFrame(const reg::SketchRegistration& registration, const reg::GeoContext& observed,
                 const Vector2d& truth_sketch, double d_cand_m, SingleFrameStats& stats) {
  const reg::CandidateDatabase& db = registration.database();
  reg::RetrievalConfig rc = reg::retrievalConfig(registration.config());
  ++stats.frames;
  for (size_t k = 0; k < kEtas.size(); ++k) {
    rc.eta = kEtas[k];
    const auto found = db.findCandidates(observed, rc);
    if (firstCorrect(found, truth_sketch, d_cand_m)) ++stats.success[k];
  }
  const auto byScore = [](std::vector<reg::Candidate> v) {
    std::stable_sort(v.begin(), v.end(), [](const reg::Candidate& a, const reg::Candidate& b) {
      return a.score > b.score;
    });
    return v;
  };
  const auto combined = byScore(db.scoreAll(observed, rc.weights, rc.try_reversed));
  const double n = static_cast<double>(std::max<size_t>(combined.size(), 1));
  if (const auto r = firstCorrect(combined, truth_sketch, d_cand_m)) {
    const reg::Candidate& c = combined[*r];
    stats.s_cos.push_back(c.s_cos);
    stats.s_fft.push_back(c.s_fft);
    stats.s_cv.push_back(c.s_cv);
    stats.s_tot.push_back(c.score);
    stats.rank_combined.push_back(1.0 - *r / n);
    if (*r < static_cast<size_t>(std::ceil(0.05 * n))) ++stats.combined_success;
  } else {
    stats.rank_combined.push_back(0.0);
  }
  reg::SimilarityWeights cosine_only;
  cosine_only.alpha_cos = 1.0;
  cosine_only.alpha_fft = 0.0;
  cosine_only.alpha_cv = 0.0;
  const auto cosine = byScore(db.scoreAll(observed, cosine_only, rc.try_reversed));
  const auto rc_rank = firstCorrect(cosine, truth_sketch, d_cand_m);
  stats.rank_cosine.push_back(rc_rank ? 1.0 - *rc_rank / n : 0.0);
  if (rc_rank && *rc_rank < static_cast<size_t>(std::ceil(0.05 * n))) ++stats.cosine_success;
}

// --------------------------------------------------------------------------------------------
// One trial.

struct TrialResult {
  uint64_t seed = 0;
  bool success = false;
  std::optional<double> ttc_s;
  double final_error_m = std::nan("");  ///< with truth: best hypothesis of the last frame with one
  double final_placement_m = std::nan("");  ///< RMS |T_est(p) - T_true(p)| of the same
  WallFit final_wall;                       ///< best hypothesis of the last frame with one
  int frames_after_ttc = 0;                 ///< frames from TTC on
  int correct_after_ttc = 0;                ///< of those, frames whose best hypothesis is a success
  double scale = std::nan("");
  int frames = 0;
  int hypotheses = 0;
  std::string final_status;
  double precompute_s = 0.0;
  size_t candidates = 0;
  std::vector<double> frame_cpu_ms;
  std::vector<double> truth_fitness_m;  ///< F of the true transform per frame (with truth)
  std::vector<double> truth_inliers;    ///< its inlier ratio
  int truth_accepted = 0;               ///< frames on which the truth passes the fitness test
};

TrialResult runTrial(const Options& opt, const sim::VoxelWorld& world, const Route& route,
                     const SketchInput& sketch, const WorldWalls& world_walls, uint64_t seed,
                     SingleFrameStats& sf) {
  TrialResult tr;
  tr.seed = seed;
  reg::SketchRegistration::Config config = opt.registration;
  config.d_gap_m = opt.d_gap_m;
  config.scale_guess = 1.0;  // the guess is already in the sketch frame (prior_inputs.h)
  const reg::RegistrationPrior prior = reg::registrationPriorFromBundle(sketch.bundle, opt.d_gap_m);
  tr.candidates = prior.candidates_sketch_m.size();
  const double cpu0 = threadCpuMs();
  reg::SketchRegistration registration(config, prior.boundary_sketch_m, prior.candidates_sketch_m);
  tr.precompute_s = (threadCpuMs() - cpu0) * 1e-3;

  std::unique_ptr<Tree2> truth_tree;
  std::unique_ptr<reg::ScaleIcp> truth_icp;
  if (sketch.T_world_sketch) {
    truth_icp =
        std::make_unique<reg::ScaleIcp>(prior.boundary_sketch_m, reg::scaleIcpConfig(config));
    reg::Points2d mapped;
    for (const Vector2d& p : prior.boundary_sketch_m)
      mapped.push_back(sketch.T_world_sketch->apply(p));
    truth_tree = treeOf(mapped);
  }
  const auto judge = [&](const Sim2& T, double* error_m, double* placement_m, WallFit* fit) {
    *fit = wallFit(prior.boundary_sketch_m, T, world_walls);
    if (truth_tree) {
      *error_m = registrationRmse(prior.boundary_sketch_m, T, *truth_tree);
      *placement_m = placementRms(prior.boundary_sketch_m, T, *sketch.T_world_sketch);
      return *placement_m <= opt.success_rmse_m;
    }
    return fit->median_m <= opt.wall_median_m && fit->inlier_ratio >= opt.wall_inlier_ratio &&
           fit->coverage >= opt.wall_inlier_ratio;
  };

  sim::LivoxLidar lidar(sim::LivoxLidarConfig{}, seed);
  efs::lio::LocalMapConfig lc;
  lc.voxel_size_m = 0.2;
  efs::lio::LocalMap map(lc);
  const double duration_s = std::min(opt.max_time_s, route.length_m / opt.speed_mps);
  const uint64_t rays_per_scan =
      static_cast<uint64_t>(lidar.config().pattern.point_rate_hz / lidar.config().frame_rate_hz);
  uint64_t k = 0;
  double next_frame_s = opt.frame_period_s;
  sim::LidarReturns returns;
  for (double t = 0.0; t <= duration_s + 1e-9; t += opt.scan_period_s) {
    const auto [p, yaw] = poseAt(route, t * opt.speed_mps);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(yaw, Vector3d::UnitZ()));
    returns.points_world.clear();
    returns.surface_world.clear();
    returns.dirs_world.clear();
    lidar.cast(world, k, k + rays_per_scan, p, q, &returns);
    k += rays_per_scan;
    map.insert(returns.points_world, p);
    if (t + 1e-9 < next_frame_s) continue;
    next_frame_s += opt.frame_period_s;
    map.crop(p);
    reg::Points3d cloud;
    for (const Eigen::Vector3f& v : map.points()) cloud.push_back(v.cast<double>());
    const double c0 = threadCpuMs();
    const reg::RegistrationResult& r = registration.addFrame(t, p, cloud);
    tr.frame_cpu_ms.push_back(threadCpuMs() - c0);
    ++tr.frames;
    tr.final_status = reg::toString(r.status);
    tr.hypotheses = static_cast<int>(r.hypotheses.size());
    bool ok = false;
    double err = std::nan(""), placement = std::nan("");
    if (!r.hypotheses.empty()) {
      WallFit fit;
      ok = judge(r.hypotheses.front().T_world_sketch, &err, &placement, &fit);
      if (ok && !tr.ttc_s) tr.ttc_s = t;
      tr.final_error_m = err;
      tr.final_placement_m = placement;
      tr.final_wall = fit;
      tr.scale = r.hypotheses.front().T_world_sketch.scale;
    }
    if (tr.ttc_s) {
      ++tr.frames_after_ttc;
      if (ok) ++tr.correct_after_ttc;
    }
    if (opt.verbose) {
      const reg::VerifierStats& vs = r.last_frame.verifier;
      std::fprintf(stderr,
                   "    t %5.0f s  %-24s hyps %d  best error %s m  %s\n"
                   "           %zu candidates; pairs %zu (scale ok %zu), triplets %zu tested, %zu "
                   "accepted, %zu tracks, %zu representatives, %zu ICP runs\n",
                   t, reg::toString(r.status), static_cast<int>(r.hypotheses.size()),
                   fmt(err).c_str(), r.message.c_str(), r.last_frame.candidates.size(),
                   vs.anchor_pairs, vs.pairs_scale_ok, vs.triplets_tested, vs.triplets_accepted,
                   vs.tracks, vs.representatives, r.last_frame.icp_runs);
    }
    if (truth_icp) {
      // What the fitness test says about the true transform on this frame's observation.
      const reg::Observation obs =
          reg::observe(cloud, p, config.observation, config.descriptor.max_range_m);
      const efs::PointKdTree2d dense(
          efs::PointKdTree2d::Points(obs.icp_dense_m.begin(), obs.icp_dense_m.end()));
      const reg::ObservedIndex index{&dense, p.head<2>()};
      const reg::IcpResult e = truth_icp->evaluate(*sketch.T_world_sketch, obs.icp_m, &index);
      if (e.num_points > 0) {
        tr.truth_fitness_m.push_back(e.fitness_m);
        tr.truth_inliers.push_back(e.inlier_ratio);
        tr.truth_accepted += e.valid && e.fitness_m <= config.fitness_threshold_m;
      }
      if (opt.verbose) {
        std::fprintf(stderr,
                     "           truth: F %.2f (forward %.2f, reverse %.2f), inliers %.2f, %d "
                     "points, valid %d\n",
                     e.fitness_m, e.forward_fitness_m, e.reverse_fitness_m, e.inlier_ratio,
                     e.num_points, e.valid);
      }
    }
    if (opt.single_frame && sketch.T_world_sketch && r.last_frame.descriptor.valid) {
      const Vector2d truth = sketch.T_world_sketch->inverse().apply(p.head<2>());
      singleFrame(registration, r.last_frame.descriptor, truth, 4.0 * opt.d_gap_m, sf);
    }
  }
  // The paper's criterion: a successful registration occurred during the flight.
  tr.success = tr.ttc_s.has_value();
  return tr;
}

Options parse(int argc, char** argv) {
  std::set<std::string> valued = sim::worldSourceOptions();
  for (const char* k : {"variant",
                        "sketch",
                        "scale-guess",
                        "trials",
                        "sketch-seed",
                        "max-time-s",
                        "speed",
                        "frame-period",
                        "scan-period",
                        "d-gap",
                        "success-rmse-m",
                        "wall-median-m",
                        "wall-inlier-ratio",
                        "markdown",
                        "require-success",
                        "fitness-threshold-m",
                        "eta",
                        "min-inlier-ratio",
                        "slice-min-dz-m",
                        "slice-max-dz-m",
                        "wall-columns",
                        "kept-fitness-threshold-m",
                        "kept-min-inlier-ratio",
                        "inlier-distance-m",
                        "column-cell-m",
                        "wall-min-height-m",
                        "wall-max-gap-m",
                        "icp-range-m"}) {
    valued.insert(k);
  }
  const efs::CliArgs args(argc, argv, valued, {"no-single-frame", "verbose"});
  Options o;
  o.world = sim::worldSourceFromArgs(args, "garage");
  o.sketch_path = args.str("sketch", "");
  if (o.sketch_path.empty()) {
    o.variant = sim::parseSketchVariant(args.str("variant", "precise"));
  } else if (args.has("variant")) {
    throw efs::CliError("give either --variant (generated sketch) or --sketch (real sketch)");
  }
  o.scale_guess_m_per_px = args.number("scale-guess", o.scale_guess_m_per_px);
  o.trials = static_cast<int>(args.integer("trials", o.trials));
  o.sketch_seed = static_cast<uint64_t>(args.integer("sketch-seed", 1));
  o.max_time_s = args.number("max-time-s", o.max_time_s);
  o.speed_mps = args.number("speed", o.speed_mps);
  o.frame_period_s = args.number("frame-period", o.frame_period_s);
  o.scan_period_s = args.number("scan-period", o.scan_period_s);
  o.d_gap_m = args.number("d-gap", o.d_gap_m);
  // A deformed sketch's truth is only its best similarity: the drawing is warped by up to 4 m.
  o.success_rmse_m = args.number(
      "success-rmse-m", o.variant == sim::SketchVariant::kDeformed ? 3.0 : o.success_rmse_m);
  o.wall_median_m = args.number("wall-median-m", o.wall_median_m);
  o.wall_inlier_ratio = args.number("wall-inlier-ratio", o.wall_inlier_ratio);
  o.markdown_path = args.str("markdown", "");
  if (args.has("require-success"))
    o.require_success = static_cast<int>(args.integer("require-success", 1));
  o.single_frame = !args.flag("no-single-frame");
  o.verbose = args.flag("verbose");
  o.registration.fitness_threshold_m =
      args.number("fitness-threshold-m", o.registration.fitness_threshold_m);
  o.registration.retrieval.eta = args.number("eta", o.registration.retrieval.eta);
  o.registration.icp.min_inlier_ratio =
      args.number("min-inlier-ratio", o.registration.icp.min_inlier_ratio);
  o.registration.observation.slice_min_dz_m =
      args.number("slice-min-dz-m", o.registration.observation.slice_min_dz_m);
  o.registration.observation.slice_max_dz_m =
      args.number("slice-max-dz-m", o.registration.observation.slice_max_dz_m);
  o.registration.kept_fitness_threshold_m =
      args.number("kept-fitness-threshold-m", o.registration.kept_fitness_threshold_m);
  o.registration.icp.inlier_distance_m =
      args.number("inlier-distance-m", o.registration.icp.inlier_distance_m);
  o.registration.kept_min_inlier_ratio =
      args.number("kept-min-inlier-ratio", o.registration.kept_min_inlier_ratio);
  o.registration.observation.wall_columns =
      args.integer("wall-columns", o.registration.observation.wall_columns ? 1 : 0) != 0;
  o.registration.observation.column_cell_m =
      args.number("column-cell-m", o.registration.observation.column_cell_m);
  o.registration.observation.wall_min_height_m =
      args.number("wall-min-height-m", o.registration.observation.wall_min_height_m);
  o.registration.observation.wall_max_gap_m =
      args.number("wall-max-gap-m", o.registration.observation.wall_max_gap_m);
  o.registration.observation.icp_range_m =
      args.number("icp-range-m", o.registration.observation.icp_range_m);
  o.registration.validate();
  efs::requireInRange("trials", o.trials, 1, 1000);
  efs::requirePositive("scale-guess", o.scale_guess_m_per_px);
  efs::requirePositive("max-time-s", o.max_time_s);
  efs::requirePositive("speed", o.speed_mps);
  efs::requirePositive("frame-period", o.frame_period_s);
  efs::requirePositive("scan-period", o.scan_period_s);
  efs::requirePositive("d-gap", o.d_gap_m);
  efs::requirePositive("success-rmse-m", o.success_rmse_m);
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options opt = parse(argc, argv);
    efs::Stopwatch wall;
    std::optional<SketchInput> real;
    if (!opt.sketch_path.empty()) {
      pm::SketchLoadConfig lc;
      lc.scale_guess_m_per_px = opt.scale_guess_m_per_px;
      real = sketchInput(pm::loadSketch(opt.sketch_path, lc));
    }
    const sim::VoxelWorld world = sim::loadWorld(opt.world);
    const Route route = planRoute(world, opt.max_time_s * opt.speed_mps);
    const std::vector<Vector2d> world_wall_points = sim::wallPoints(world, world.sketch_band);
    WorldWalls world_walls;
    world_walls.tree = treeOf(reg::Points2d(world_wall_points.begin(), world_wall_points.end()));
    for (size_t i = 0; i < world_wall_points.size(); i += 1 + world_wall_points.size() / 5000) {
      world_walls.sample.push_back(world_wall_points[i]);
    }
    const std::string scene = opt.variant ? sim::sketchVariantName(*opt.variant)
                                          : opt.sketch_path.substr(opt.sketch_path.rfind('/') + 1);
    std::fprintf(stderr, "registration_eval: %s, %s sketch, route %.0f m (%zu waypoints)\n",
                 opt.world.describe().c_str(), scene.c_str(), route.length_m,
                 route.waypoints_m.size());

    SingleFrameStats sf;
    std::vector<TrialResult> trials;
    for (int i = 0; i < opt.trials; ++i) {
      const uint64_t seed = opt.sketch_seed + static_cast<uint64_t>(i);
      try {
        const SketchInput sketch = real ? *real : generatedSketch(world, *opt.variant, seed);
        trials.push_back(runTrial(opt, world, route, sketch, world_walls, seed, sf));
      } catch (const std::exception& e) {
        // A drawn variant the pre-processing refuses (e.g. a partial sketch with no region left)
        // is a failed trial, reported, not the end of the evaluation.
        TrialResult failed;
        failed.seed = seed;
        failed.final_status = std::string("sketch refused: ") + e.what();
        trials.push_back(failed);
      }
      const TrialResult& t = trials.back();
      std::fprintf(stderr,
                   "  trial %d (seed %llu): %s, TTC %s s, error %s m, wall median %s m, %d frames, "
                   "status %s; truth F median %s m, inliers median %s, accepted on %d frames\n",
                   i + 1, static_cast<unsigned long long>(seed), t.success ? "success" : "FAILURE",
                   t.ttc_s ? fmt(*t.ttc_s, 0).c_str() : "-", fmt(t.final_error_m).c_str(),
                   fmt(t.final_wall.median_m).c_str(), t.frames, t.final_status.c_str(),
                   fmt(median(t.truth_fitness_m)).c_str(), fmt(median(t.truth_inliers)).c_str(),
                   t.truth_accepted);
    }

    std::ostringstream md;
    md << "## Registration on " << opt.world.describe() << ", " << scene << " sketch\n\n";
    md << "Route " << fmt(route.length_m, 0) << " m at " << fmt(opt.speed_mps, 1)
       << " m/s, a frame every " << fmt(opt.frame_period_s, 1) << " s (at most "
       << fmt(opt.max_time_s, 0) << " s), d_gap " << fmt(opt.d_gap_m, 1) << " m";
    if (!real) {
      md << ", success: placement error (RMS of |T_est(p) - T_true(p)| over the sketch walls) <= "
         << fmt(opt.success_rmse_m, 1)
         << " m; error = the paper's RMSE of closest point pairs (estimate vs truth mapping)";
    }
    if (real) {
      md << ", success: wall median <= " << fmt(opt.wall_median_m, 2)
         << " m, >= " << pct(opt.wall_inlier_ratio)
         << " of sketch walls within 1 m of a world wall and >= " << pct(opt.wall_inlier_ratio)
         << " of world walls within 1 m of a mapped sketch wall";
    }
    md << ".\n\n";
    if (sf.frames > 0) {
      const double n = sf.frames;
      md << "### Single-frame retrieval (d_cand = " << fmt(4 * opt.d_gap_m, 1) << " m)\n\n";
      md << "| scene | frames | succ. eta 10 % | succ. eta 5 % | succ. eta 2.5 % | Cos. sim. | FFT "
            "sim. | CV sim. | Tot. sim. |\n|---|---|---|---|---|---|---|---|---|\n";
      md << "| " << scene << " | " << sf.frames << " | " << pct(sf.success[0] / n) << " | "
         << pct(sf.success[1] / n) << " | " << pct(sf.success[2] / n) << " | "
         << fmt(mean(sf.s_cos)) << " | " << fmt(mean(sf.s_fft)) << " | " << fmt(mean(sf.s_cv))
         << " | " << fmt(mean(sf.s_tot), 3) << " |\n\n";
      md << "### Ranking-score ablation (1 - rank / N of the best-ranked correct candidate)\n\n";
      md << "| ranking | mean | std | min | correct in top 5 % (before downsampling) "
            "|\n|---|---|---|---|---|\n";
      md << "| combined (0.4 / 0.4 / 0.2) | " << fmt(mean(sf.rank_combined), 3) << " | "
         << fmt(stddev(sf.rank_combined), 3) << " | "
         << fmt(*std::min_element(sf.rank_combined.begin(), sf.rank_combined.end()), 3) << " | "
         << pct(sf.combined_success / n) << " |\n";
      md << "| cosine only | " << fmt(mean(sf.rank_cosine), 3) << " | "
         << fmt(stddev(sf.rank_cosine), 3) << " | "
         << fmt(*std::min_element(sf.rank_cosine.begin(), sf.rank_cosine.end()), 3) << " | "
         << pct(sf.cosine_success / n) << " |\n\n";
    }
    md << "### Overall registration\n\n";
    md << "| trial | seed | success | TTC [s] | error [m] | placement [m] | wall median [m] | "
          "sketch walls on "
          "world "
          "walls | world walls covered | "
          "scale | right after TTC | hyps | status | candidates | Phase 1 [s] | frame median [ms] "
          "| frame max [ms] "
          "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::vector<double> ttcs, errors, all_frames;
    int successes = 0;
    for (size_t i = 0; i < trials.size(); ++i) {
      const TrialResult& t = trials[i];
      if (t.success) {
        ++successes;
        ttcs.push_back(*t.ttc_s);
        if (std::isfinite(t.final_error_m)) errors.push_back(t.final_error_m);
      }
      all_frames.insert(all_frames.end(), t.frame_cpu_ms.begin(), t.frame_cpu_ms.end());
      md << "| " << i + 1 << " | " << t.seed << " | " << (t.success ? "yes" : "**no**") << " | "
         << (t.ttc_s ? fmt(*t.ttc_s, 0) : "-") << " | " << fmt(t.final_error_m) << " | "
         << fmt(t.final_placement_m) << " | " << fmt(t.final_wall.median_m) << " | "
         << pct(t.final_wall.inlier_ratio) << " | " << pct(t.final_wall.coverage) << " | "
         << fmt(t.scale, 3) << " | "
         << (t.frames_after_ttc ? pct(double(t.correct_after_ttc) / t.frames_after_ttc) : "-")
         << " | " << t.hypotheses << " | " << t.final_status << " | " << t.candidates << " | "
         << fmt(t.precompute_s) << " | " << fmt(median(t.frame_cpu_ms), 0) << " | "
         << fmt(t.frame_cpu_ms.empty()
                    ? std::nan("")
                    : *std::max_element(t.frame_cpu_ms.begin(), t.frame_cpu_ms.end()),
                0)
         << " |\n";
    }
    md << "\n| scene | TTC [s] (successes) | error [m] (successes) | success "
          "|\n|---|---|---|---|\n";
    md << "| " << scene << " | " << fmt(mean(ttcs), 1) << " | " << fmt(mean(errors)) << " | "
       << successes << " / " << trials.size() << " |\n\n";
    md << "Frame update CPU time over all trials: median " << fmt(median(all_frames), 0)
       << " ms; evaluation wall time " << fmt(wall.elapsedSeconds(), 0) << " s.\n";
    std::cout << md.str() << std::flush;
    if (!opt.markdown_path.empty()) {
      std::ofstream out(opt.markdown_path, std::ios::app);
      if (!out) throw std::runtime_error("cannot write " + opt.markdown_path);
      out << md.str() << "\n";
    }
    if (opt.require_success && successes < *opt.require_success) {
      std::fprintf(stderr, "registration_eval: %d of %zu trials succeeded, %d required\n",
                   successes, trials.size(), *opt.require_success);
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "registration_eval: %s\n", e.what());
    return 2;
  }
}
