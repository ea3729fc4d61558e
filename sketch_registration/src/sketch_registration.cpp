// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/sketch_registration.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>

#include "efs_common/config_check.h"
#include "sketch_registration/sim2_fit.h"

namespace efs::registration {

namespace {
/// New inputs whose window fitness is within this factor of F_thresh get the joint refinement.
constexpr double kJointFitnessFactor = 1.5;
}  // namespace

const char* toString(RegistrationStatus status) {
  switch (status) {
    case RegistrationStatus::kOk:
      return "ok";
    case RegistrationStatus::kTooFewFrames:
      return "too_few_frames";
    case RegistrationStatus::kNoConsistentTriplet:
      return "no_consistent_triplet";
    case RegistrationStatus::kAllRejectedByFitness:
      return "all_rejected_by_fitness";
    case RegistrationStatus::kNoCandidates:
      return "no_candidates";
    case RegistrationStatus::kBadInput:
      return "bad_input";
    case RegistrationStatus::kOdometryJump:
      return "odometry_jump";
    case RegistrationStatus::kMirroredSketch:
      return "mirrored_sketch";
    case RegistrationStatus::kAwaitingConfirmation:
      return "awaiting_confirmation";
  }
  return "unknown";
}

void SketchRegistrationConfig::validate() const {
  requirePositive("d_gap_m", d_gap_m);
  requirePositive("scale_guess", scale_guess);
  requireInRange("scale_tolerance_factor", scale_tolerance_factor, 1.0, 1e3);
  requireInRange("scale_levels", scale_levels, 1, 64);
  requireInRange("sketch_point_radius_m", sketch_point_radius_m, 0.0, 100.0);
  requirePositive("fitness_threshold_m", fitness_threshold_m);
  requireThat(kept_fitness_threshold_m >= fitness_threshold_m, "kept_fitness_threshold_m",
              "must be >= fitness_threshold_m (a kept hypothesis is held to a looser bound)");
  requireThat(kept_min_inlier_ratio >= 0.0 && kept_min_inlier_ratio <= icp.min_inlier_ratio,
              "kept_min_inlier_ratio", "must be in [0, min_inlier_ratio]");
  requireThat(kept_min_inside_ratio >= 0.0 && kept_min_inside_ratio <= icp.min_inside_ratio,
              "kept_min_inside_ratio", "must be in [0, min_inside_ratio]");
  requireInRange("confirm_frames", confirm_frames, 1, 100);
  requireInRange("confidence_tau", confidence_tau, 0.0, 1e3);
  requireInRange("settled_coverage", settled_coverage, 0.0, 1.0);
  requireInRange("kept_drawing_reach_m", kept_drawing_reach_m, 0.0, 1e3);
  requireInRange("kept_drawing_reach_min_age_frames", kept_drawing_reach_min_age_frames, 0,
                 1000000);
  requireInRange("coverage_weight_m", coverage_weight_m, 0.0, 1e3);
  requirePositive("max_speed_mps", max_speed_mps);
  requireInRange("max_icp_inputs", max_icp_inputs, 1, 100000);
  requireInRange("screen_points", screen_points, 0, 100000);
  requireInRange("screen_iterations", screen_iterations, 1, 1000);
  requireInRange("icp_retry_frames", icp_retry_frames, 0, 100000);
  requireInRange("dormant_frames", dormant_frames, 0, 100000);
  requireInRange("mirror_min_age_frames", mirror_min_age_frames, 1, 100000);
  requireInRange("mirror_dominance_coverage", mirror_dominance_coverage, 0.0, 1.0);
  requireInRange("max_hypotheses", max_hypotheses, 1, 100000);
  requirePositive("merge_distance", merge_distance);
  history.validate();
  requireInRange("history_inlier_slack", history_inlier_slack, 0.0, 1.0);
  requireInRange("history_min_inlier_ratio", history_min_inlier_ratio, 0.0, 1.0);
  requireInRange("history_inlier_margin", history_inlier_margin, 0.0, 1.0);
  requireThat(history_kept_min_inlier_ratio >= 0.0 &&
                  history_kept_min_inlier_ratio <= history_min_inlier_ratio,
              "history_kept_min_inlier_ratio", "must be in [0, history_min_inlier_ratio]");
  sketchDescriptorConfig(*this).validate();
  observationDescriptorConfig(*this).validate();
  retrievalConfig(*this).validate();
  verifierConfig(*this).validate();
  scaleIcpConfig(*this).validate();
  requireInRange("stretch_min_fitness_gain", stretch_min_fitness_gain, 0.0, 1.0);
  observation.validate();
}

DescriptorConfig sketchDescriptorConfig(const SketchRegistrationConfig& c) {
  DescriptorConfig d = c.descriptor;
  // The observation's range limit in sketch metres at the smallest admissible scale: the sketch
  // then sees at least as far as the observation whatever the true scale, and what lies beyond
  // the observation's range falls in bins it leaves empty (DescriptorConfig::
  // empty_observed_bins_unknown). At the guessed scale alone, a sketch drawn larger than guessed
  // (true scale 0.5-0.85 in the garage's scaled variant) had empty bins where the observation saw
  // walls 15-30 m away (single-frame success 76 % instead of 100 %).
  d.max_range_m = c.descriptor.max_range_m * c.scale_tolerance_factor / c.scale_guess;
  d.min_range_m = c.descriptor.min_range_m / c.scale_guess;
  d.point_radius_m = c.sketch_point_radius_m;
  return d;
}

std::vector<double> sketchRangeLevelsM(const SketchRegistrationConfig& c) {
  // Scale s_g f^(1 - 2l/(L-1)), l = 0..L-1: the range limit R / s from R f / s_g down to
  // R / (s_g f). One level: the scale guess.
  const int n = c.scale_levels;
  const double r = c.descriptor.max_range_m / c.scale_guess;
  // Never past the descriptor's own range (the same product, rounded another way).
  const double longest_m = sketchDescriptorConfig(c).max_range_m;
  std::vector<double> levels;
  for (int l = 0; l < n; ++l) {
    const double e = n > 1 ? 1.0 - 2.0 * l / (n - 1) : 0.0;
    levels.push_back(std::min(r * std::pow(c.scale_tolerance_factor, e), longest_m));
  }
  return levels;
}

DescriptorConfig observationDescriptorConfig(const SketchRegistrationConfig& c) {
  DescriptorConfig d = c.descriptor;
  d.point_radius_m = std::max(c.descriptor.point_radius_m, 0.5 * c.observation.column_cell_m);
  return d;
}

VerifierConfig verifierConfig(const SketchRegistrationConfig& c) {
  VerifierConfig v = c.verifier;
  v.scale_guess = c.scale_guess;
  v.scale_tolerance_factor = c.scale_tolerance_factor;
  v.allow_reflection = c.reflection != ReflectionMode::kIgnore;
  return v;
}

ScaleIcpConfig scaleIcpConfig(const SketchRegistrationConfig& c) {
  ScaleIcpConfig s = c.icp;
  s.scale_min = c.scale_guess / c.scale_tolerance_factor;
  s.scale_max = c.scale_guess * c.scale_tolerance_factor;
  return s;
}

RetrievalConfig retrievalConfig(const SketchRegistrationConfig& c) {
  RetrievalConfig r = c.retrieval;
  r.try_reversed = c.reflection != ReflectionMode::kIgnore;
  return r;
}

void rankHypotheses(std::vector<Hypothesis>& hs, double tau, double coverage_weight_m) {
  const auto key = [&](const Hypothesis& h) {
    return h.fitness_m + coverage_weight_m * (1.0 - h.coverage);
  };
  double z = 0.0;
  for (const auto& h : hs) z += std::exp(-tau * key(h));
  for (auto& h : hs) h.confidence = std::exp(-tau * key(h)) / z;
  std::stable_sort(hs.begin(), hs.end(),
                   [&](const Hypothesis& a, const Hypothesis& b) { return key(a) < key(b); });
}

namespace {
SketchRegistrationConfig validated(const SketchRegistrationConfig& c) {
  c.validate();
  return c;
}
}  // namespace

SketchRegistration::SketchRegistration(const Config& config, Points2d sketch_boundary_m,
                                       Points2d candidates_m)
    : config_(validated(config)), verifier_(verifierConfig(config_)), history_(config_.history) {
  for (const auto& p : sketch_boundary_m) {
    if (p.allFinite()) sketch_.push_back(p);
  }
  database_ = CandidateDatabase(sketch_, std::move(candidates_m), sketchDescriptorConfig(config_),
                                sketchRangeLevelsM(config_));
  ScaleIcpConfig similarity = scaleIcpConfig(config_);
  similarity.max_stretch = 1.0;
  icp_ = std::make_unique<ScaleIcp>(sketch_, similarity);
  if (config_.icp.max_stretch > 1.0) {
    stretch_icp_ = std::make_unique<ScaleIcp>(icp_->sketchIndex(), scaleIcpConfig(config_));
  }
  ScaleIcpConfig screen = similarity;
  screen.coarse_yaw_steps = screen.coarse_scale_steps = 0;
  screen.max_iterations = config_.screen_iterations;
  screen.iteration_points = 0;
  screen.symmetric = false;
  screen_icp_ = std::make_unique<ScaleIcp>(icp_->sketchIndex(), screen);
}

void SketchRegistration::reset() {
  verifier_.reset();
  history_.reset();
  live_.clear();
  dormant_.clear();
  rejected_.clear();
  last_observation_.reset();
  result_ = RegistrationResult{};
  has_last_ = false;
}

HistoryFit SketchRegistration::historyFit(const Sim2& T) const {
  return icp_->historyFit(T, history_.beyond());
}

IcpResult SketchRegistration::evaluateOnLastFrame(const Sim2& T) const {
  if (!last_observation_) return IcpResult{};
  const ObservedIndex observed{&last_observation_->dense, last_observation_->robot_world_m};
  return icp_->evaluate(T, last_observation_->icp_points, &observed);
}

bool SketchRegistration::historyInUse() const {
  return config_.history.enabled &&
         history_.beyondCount() >= static_cast<size_t>(config_.history.min_points);
}

RegistrationResult& SketchRegistration::fail(RegistrationStatus status,
                                             const std::string& message) {
  result_.status = status;
  result_.message = message;
  return result_;
}

const RegistrationResult& SketchRegistration::addFrame(double time_s,
                                                       const Eigen::Vector3d& robot_world_m,
                                                       const Points3d& local_map_world_m) {
  FrameDiagnostics diag;
  diag.time_s = time_s;
  result_.last_frame = diag;
  last_observation_.reset();
  if (!std::isfinite(time_s) || !robot_world_m.allFinite()) {
    return fail(RegistrationStatus::kBadInput, "non-finite time or robot position; frame ignored");
  }
  if (has_last_ && !(time_s > last_time_s_)) {
    return fail(RegistrationStatus::kBadInput, "time does not increase; frame ignored");
  }
  if (database_.validCount() == 0) {
    return fail(RegistrationStatus::kNoCandidates,
                "the sketch has no candidate location with a usable descriptor (" +
                    std::to_string(database_.size()) + " candidates, " +
                    std::to_string(sketch_.size()) + " boundary points)");
  }
  const Eigen::Vector2d robot_xy = robot_world_m.head<2>();
  diag.robot_world_m = robot_xy;
  if (has_last_) {
    const double speed = (robot_xy - last_robot_m_).norm() / (time_s - last_time_s_);
    if (speed > config_.max_speed_mps) {
      std::ostringstream os;
      os << "robot moved at " << speed << " m/s since the last frame (> max_speed_mps "
         << config_.max_speed_mps << "); registration restarted";
      reset();
      has_last_ = true;
      last_time_s_ = time_s;
      last_robot_m_ = robot_xy;
      result_.last_frame = diag;
      return fail(RegistrationStatus::kOdometryJump, os.str());
    }
  }
  has_last_ = true;
  last_time_s_ = time_s;
  last_robot_m_ = robot_xy;

  // One observation for both consumers (observation.h).
  Observation obs = observe(local_map_world_m, robot_world_m, config_.observation,
                            config_.descriptor.max_range_m);
  diag.descriptor_points = obs.descriptor_m.size();
  const DescriptorConfig odc = observationDescriptorConfig(config_);
  diag.descriptor = computeObservedGeoContext(
      obs.descriptor_m, {&obs.map.points_m, &obs.map.passage_m, &obs.map.other_m}, robot_xy, odc);
  result_.last_frame = diag;
  if (!diag.descriptor.valid) {
    std::ostringstream os;
    if (obs.map.num_in_band == 0) {
      os << "local map unusable: " << obs.map.num_input << " points, " << obs.map.num_non_finite
         << " non-finite, none in the height band within range; frame ignored";
    } else {
      // A sound map whose view holds too little wall: in an aisle lined with parked cars, only
      // the far ends. Said so, not blamed on the map.
      os << "too few walls in view for a descriptor: the view ends within "
         << config_.descriptor.max_range_m << " m in only " << diag.descriptor.described_bins
         << " of " << diag.descriptor.range_m.size() << " bearings ("
         << config_.descriptor.min_valid_bins << " needed), " << obs.descriptor_m.size()
         << " wall points in that range; " << obs.map.num_in_band
         << " local-map points in the height band, " << obs.map.num_low_obstacle_columns
         << " columns of low obstacles (cars) not counted as walls; frame ignored";
    }
    return fail(RegistrationStatus::kBadInput, os.str());
  }

  diag.candidates = database_.findCandidates(diag.descriptor, retrievalConfig(config_));
  diag.used_for_verification = verifier_.addFrame(robot_xy, diag.candidates);
  if (diag.used_for_verification) diag.verifier = verifier_.lastStats();
  diag.representatives = verifier_.representatives().size();
  result_.frames_used = verifier_.numFrames();

  diag.icp_points = obs.icp_m.size();
  last_observation_.emplace();
  last_observation_->icp_points = std::move(obs.icp_m);
  last_observation_->dense.reset(
      PointKdTree2d::Points(obs.icp_dense_m.begin(), obs.icp_dense_m.end()));
  last_observation_->robot_world_m = robot_xy;
  const ObservedIndex observed{&last_observation_->dense, robot_xy};
  history_.update(robot_xy, obs.icp_dense_m, obs.passage_m, config_.observation.icp_range_m);
  updateHypotheses(last_observation_->icp_points, observed, diag);
  result_.last_frame = diag;
  // No transform survived the fitness test: whatever tracks the verifier still follows are not
  // registrations, so the next frame seeds fresh triplets as well. In detect mode a surviving
  // mirror-image fit counts as none: a passage fits its own mirror image, a drawing is rarely
  // mirrored, and the proper transform must still be searched for (a mirror track that survived
  // 35 s of a cave flight kept it from being found). Nor does a fit that leaves much of the
  // observation unexplained (settled_coverage): a shrunken placement of a hand drawing on an
  // office's repetitive walls survived ed21's whole flight, and the three frames of the true
  // placement's candidates that came later were never combined.
  const bool settled = std::any_of(live_.begin(), live_.end(), [&](const Hypothesis& h) {
    return (!h.T_world_sketch.reflected || config_.reflection != ReflectionMode::kDetect) &&
           h.coverage >= config_.settled_coverage;
  });
  if (!settled) verifier_.requestReseed();

  result_.hypotheses.clear();
  result_.mirrored_hypotheses.clear();
  size_t awaiting = 0;
  for (const Hypothesis& h : live_) {
    if (h.T_world_sketch.reflected && config_.reflection == ReflectionMode::kDetect) {
      result_.mirrored_hypotheses.push_back(h);
    } else if (h.age_frames >= config_.confirm_frames) {
      result_.hypotheses.push_back(h);
    } else {
      ++awaiting;
    }
  }
  const auto bestCoverage = [](const std::vector<Hypothesis>& hs) {
    double c = 0.0;
    for (const Hypothesis& h : hs) c = std::max(c, h.coverage);
    return c;
  };
  const bool mirror_persisted = std::any_of(
      result_.mirrored_hypotheses.begin(), result_.mirrored_hypotheses.end(),
      [&](const Hypothesis& h) { return h.age_frames >= config_.mirror_min_age_frames; });
  const double mirror_coverage = bestCoverage(result_.mirrored_hypotheses);
  const double proper_coverage = bestCoverage(result_.hypotheses);
  const bool mirror_dominates =
      mirror_persisted && !result_.hypotheses.empty() &&
      mirror_coverage >= proper_coverage + config_.mirror_dominance_coverage;
  if (mirror_dominates) result_.hypotheses.clear();
  rankHypotheses(result_.hypotheses, config_.confidence_tau, config_.coverage_weight_m);
  rankHypotheses(result_.mirrored_hypotheses, config_.confidence_tau, config_.coverage_weight_m);
  result_.best_is_mirrored =
      !result_.hypotheses.empty() && result_.hypotheses.front().T_world_sketch.reflected;

  std::ostringstream os;
  if (!result_.hypotheses.empty()) {
    result_.status = RegistrationStatus::kOk;
    os << result_.hypotheses.size() << " hypotheses; best F = " << result_.hypotheses[0].fitness_m
       << " m" << (result_.best_is_mirrored ? " (mirror-image sketch)" : "");
  } else if (mirror_persisted) {
    result_.status = RegistrationStatus::kMirroredSketch;
    if (mirror_dominates)
      os << "mirror-image transforms explain far more of the observation than the others "
            "(coverage "
         << mirror_coverage << " against " << proper_coverage << "): the sketch looks mirrored";
    else
      os << "only mirror-image transforms fit the sketch (best F = "
         << result_.mirrored_hypotheses[0].fitness_m << " m): the sketch looks mirrored";
  } else if (awaiting > 0) {
    result_.status = RegistrationStatus::kAwaitingConfirmation;
    os << awaiting << " new transform(s) passed the fitness test; reported once confirmed on "
       << config_.confirm_frames << " consecutive frames";
  } else if (verifier_.numFrames() < 3) {
    result_.status = RegistrationStatus::kTooFewFrames;
    os << verifier_.numFrames() << " of 3 frames"
       << (diag.used_for_verification
               ? ""
               : " (this frame too close to the last or without candidates)");
  } else if (diag.icp_runs == 0) {
    result_.status = RegistrationStatus::kNoConsistentTriplet;
    os << "no consistent triplet over " << verifier_.numFrames() << " frames";
  } else {
    result_.status = RegistrationStatus::kAllRejectedByFitness;
    os << diag.icp_runs << " transforms refined, none with F below " << config_.fitness_threshold_m
       << " m";
  }
  result_.message = os.str();
  return result_;
}

std::vector<Sim2> SketchRegistration::newInputs(const Points2d& icp_points) const {
  std::vector<Sim2> fresh;
  for (const Representative& r : verifier_.representatives()) {
    if (config_.screen_points == 0 && static_cast<int>(fresh.size()) >= config_.max_icp_inputs)
      break;
    // A representative already tracked by a live hypothesis only costs a refinement. One near a
    // dormant hypothesis is refined too, with the wide capture radius: the dormant one's narrow
    // refinement is what failed.
    bool known = false;
    for (const Hypothesis& h : live_) {
      if (transformDistance(h.T_world_sketch, r.T_world_sketch, config_.verifier.lambda) <
          config_.merge_distance) {
        known = true;
        break;
      }
    }
    // Transforms that just failed the fitness test wait a few frames for the map to grow.
    for (const Rejected& x : rejected_) {
      if (transformDistance(x.T, r.T_world_sketch, config_.verifier.lambda) <
          config_.merge_distance) {
        known = true;
        break;
      }
    }
    if (known) continue;
    fresh.push_back(r.T_world_sketch);
  }
  if (static_cast<int>(fresh.size()) <= config_.max_icp_inputs) return fresh;
  // Half the budget keeps the verifier's order (the best supported tracks: a distorted drawing's
  // true track, which a nearby wrong placement can outscore on one frame's window); the other
  // half goes to the best screened among the rest.
  const size_t by_support = static_cast<size_t>(config_.max_icp_inputs / 2);
  const Points2d sample = thinEvenly(icp_points, static_cast<size_t>(config_.screen_points));
  std::vector<std::pair<double, size_t>> score;
  for (size_t k = by_support; k < fresh.size(); ++k) {
    const IcpResult r = screen_icp_->refine(fresh[k], sample);
    // Ties (a common inlier share) go to the smaller fitness, then to the verifier's order; a
    // failed fit (no points inside the sketch: NaN) goes last.
    const double s = r.forward_inlier_ratio - 1e-3 * std::min(r.fitness_m, 100.0);
    score.push_back({std::isfinite(s) ? s : -1.0, k});
  }
  std::stable_sort(score.begin(), score.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<Sim2> out(fresh.begin(), fresh.begin() + static_cast<long>(by_support));
  for (size_t k = 0; out.size() < static_cast<size_t>(config_.max_icp_inputs); ++k)
    out.push_back(fresh[score[k].second]);
  return out;
}

IcpResult SketchRegistration::refineLive(const Sim2& T, const Points2d& points,
                                         double start_correspondence_m,
                                         const ObservedIndex& observed) const {
  if (!stretch_icp_) return icp_->refine(T, points, start_correspondence_m, &observed);
  // The similarity competes from the one closest to T over these walls: T without its stretch
  // lies metres off far from the sketch's origin.
  Sim2 T_similarity(T.yaw_rad, T.scale, T.t_m, T.reflected);
  if (!T.isSimilarity()) {
    const Sim2 T_inverse = T.inverse();
    const Eigen::Matrix2d to_sketch = T_inverse.linear();  // once, not per point (Sim2::apply)
    Points2d sketch_m;
    sketch_m.reserve(points.size());
    for (const auto& p : points) sketch_m.push_back(to_sketch * p + T_inverse.t_m);
    const Sim2Fit closest = fitSim2(sketch_m, points, T.reflected);
    if (closest.ok) T_similarity = closest.T_world_sketch;
  }
  return stretchedIfBetter(icp_->refine(T_similarity, points, start_correspondence_m, &observed), T,
                           points, start_correspondence_m, observed);
}

IcpResult SketchRegistration::stretchedIfBetter(const IcpResult& similarity, const Sim2& T,
                                                const Points2d& points,
                                                double start_correspondence_m,
                                                const ObservedIndex& observed) const {
  const IcpResult stretched = stretch_icp_->refine(T, points, start_correspondence_m, &observed);
  const bool stretch_earns_its_place =
      stretched.usable && !stretched.T_world_sketch.isSimilarity() &&
      (!similarity.usable ||
       stretched.fitness_m < (1.0 - config_.stretch_min_fitness_gain) * similarity.fitness_m);
  return stretch_earns_its_place ? stretched : similarity;
}

void SketchRegistration::updateHypotheses(const Points2d& icp_points, const ObservedIndex& observed,
                                          FrameDiagnostics& diag) {
  struct Input {
    std::optional<int> id;  ///< empty: a new transform, not yet a hypothesis
    int age;
    Sim2 T;
  };
  std::vector<Input> inputs;
  // Expire rejections before this frame's representatives are checked against them: a transform
  // rejected on frame k waits icp_retry_frames frames and is refined again on frame
  // k + icp_retry_frames + 1 (expired after the check, it waited one frame more, and with 0 it
  // still skipped the next frame).
  ++frame_counter_;
  rejected_.erase(std::remove_if(rejected_.begin(), rejected_.end(),
                                 [&](const Rejected& x) {
                                   return frame_counter_ - x.frame >
                                          static_cast<size_t>(config_.icp_retry_frames);
                                 }),
                  rejected_.end());
  for (const Hypothesis& h : live_) inputs.push_back({h.id, h.age_frames, h.T_world_sketch});
  for (const Dormant& d : dormant_) inputs.push_back({d.h.id, d.h.age_frames, d.h.T_world_sketch});
  for (const Sim2& T : newInputs(icp_points)) inputs.push_back({std::nullopt, 0, T});
  struct Refined {
    std::optional<int> id;
    int age;
    IcpResult r;
    HistoryFit history;
  };
  std::vector<Refined> refined;
  // Walls seen earlier beyond the window join the refinement: they pin the scale and yaw that
  // the window leaves loose (see observation_history.h).
  const bool use_history = historyInUse();
  Points2d joint;
  if (use_history) {
    joint = icp_points;
    joint.insert(joint.end(), history_.beyond().begin(), history_.beyond().end());
  }
  const double narrow_m = 1.5 * config_.icp.min_correspondence_m;
  // The bounds a fit is held to: a reported (confirmed) hypothesis to the looser kept ones. A new
  // transform must lay the sketch over icp.min_inside_ratio of the observation (else it put the
  // sketch somewhere else); a reported one only over kept_min_inside_ratio: walking beyond a
  // partial sketch, the true placement's share falls while what lies inside still fits (office
  // drawn west of 30 m: 0.16-0.25 inside at F 0.03-0.04 m, inliers 0.86-0.89).
  struct FitBounds {
    double max_fitness_m, min_inliers, min_inside, min_history_inliers;
  };
  const FitBounds new_bounds{config_.fitness_threshold_m, config_.icp.min_inlier_ratio,
                             config_.icp.min_inside_ratio, config_.history_min_inlier_ratio};
  const FitBounds kept_bounds{config_.kept_fitness_threshold_m, config_.kept_min_inlier_ratio,
                              config_.kept_min_inside_ratio, config_.history_kept_min_inlier_ratio};
  for (const Input& in : inputs) {
    const bool reported = in.id && in.age >= config_.confirm_frames;
    const FitBounds& bounds = reported ? kept_bounds : new_bounds;
    const auto judged = [&](const IcpResult& x) {
      return x.usable && x.inside_ratio >= bounds.min_inside;
    };
    // Live hypotheses were refined last frame: a narrow capture radius suffices.
    IcpResult r = in.id ? refineLive(in.T, icp_points, narrow_m, observed)
                        : icp_->refine(in.T, icp_points, 0.0, &observed);
    // A new transform that fits the window nearly well enough as a similarity may fit it with a
    // stretch (a drawing whose aspect is off); one far off is not given the extra freedom.
    if (!in.id && stretch_icp_ && r.usable &&
        r.fitness_m <= kJointFitnessFactor * config_.fitness_threshold_m) {
      r = stretchedIfBetter(r, r.T_world_sketch, icp_points, narrow_m, observed);
    }
    // A new input whose window fit is far from the new-hypothesis bounds is not refined again
    // over the remembered walls: the joint fit is judged by the window's fit at its transform,
    // which the window's own refinement already optimised (on a 190 x 150 m garage ~120 inputs a
    // frame, most of them far off).
    if (use_history &&
        (in.id ||
         (judged(r) &&
          config_.icp.inliersPass(r, config_.icp.min_inlier_ratio - config_.history_inlier_slack) &&
          r.fitness_m <= kJointFitnessFactor * config_.fitness_threshold_m))) {
      // A live hypothesis continues from its own (joint) transform: refined on the window first,
      // it would slide back to the window's loose optimum, metres off at the remembered walls
      // and beyond the narrow capture radius. A new one starts from its window fit, with the
      // wide radius (a 2 % scale error is 2 m at 100 m).
      const IcpResult g = in.id ? refineLive(in.T, joint, narrow_m, observed)
                                : icp_->refine(r.T_world_sketch, joint,
                                               config_.icp.max_correspondence_m, &observed);
      // The window's own fit at the joint transform decides, as without a history.
      const IcpResult e = icp_->evaluate(g.T_world_sketch, icp_points, &observed);
      if (judged(e) &&
          (!judged(r) || e.inlierRatio() >= r.inlierRatio() - config_.history_inlier_slack)) {
        r = e;
      }
    }
    ++diag.icp_runs;
    const auto passes = [&](const IcpResult& x) {
      return judged(x) && config_.icp.inliersPass(x, bounds.min_inliers) &&
             x.fitness_m <= bounds.max_fitness_m;
    };
    if (reported && config_.kept_drawing_reach_m > 0.0 &&
        in.age >= config_.kept_drawing_reach_min_age_frames && !passes(r)) {
      const IcpResult near_drawing =
          icp_->evaluate(r.T_world_sketch, icp_points, &observed, config_.kept_drawing_reach_m);
      if (passes(near_drawing)) r = near_drawing;
    }
    if (!passes(r)) {
      if (!in.id) rejected_.push_back({in.T, frame_counter_});
      continue;
    }
    HistoryFit hf;
    if (use_history) {
      hf = historyFit(r.T_world_sketch);
      if (hf.inside >= config_.history.min_points &&
          !(hf.inlierRatio() >= bounds.min_history_inliers)) {
        if (!in.id) rejected_.push_back({in.T, frame_counter_});
        continue;
      }
    }
    refined.push_back({in.id, in.age, r, hf});
  }
  std::stable_sort(refined.begin(), refined.end(), [](const Refined& a, const Refined& b) {
    return a.r.fitness_m < b.r.fitness_m;
  });
  std::vector<Refined> kept;
  for (const Refined& f : refined) {
    bool merged = false;
    for (Refined& k : kept) {
      if (transformDistance(k.r.T_world_sketch, f.r.T_world_sketch, config_.verifier.lambda) <
          config_.merge_distance) {
        // The oldest id survives a merge, so a hypothesis keeps its id while it lives.
        if (f.id && (!k.id || *f.id < *k.id)) {
          k.id = f.id;
          k.age = std::max(k.age, f.age);
        }
        merged = true;
        break;
      }
    }
    if (!merged) kept.push_back(f);
  }
  // Hypotheses compete on the remembered walls: along a repetitive passage a placement one
  // module off fits the window and the straight walls behind as well as the truth, and only the
  // distinct parts seen earlier tell them apart (synthetic corridor of identical rooms: the truth
  // lays 0.92 of the remembered walls on the sketch, placements 16 and 32 m off 0.65-0.81).
  // Only a reported (confirmed) hypothesis sets the bar: a new transform that fits one frame's
  // remembered walls better must first be confirmed before it displaces an established one
  // (a mildly deformed office drawing lost its true placement to such one-frame fits).
  double best_history = -1.0;
  for (const Refined& k : kept) {
    if (k.history.inside >= config_.history.min_points && k.age + 1 >= config_.confirm_frames) {
      best_history = std::max(best_history, k.history.inlierRatio());
    }
  }
  kept.erase(std::remove_if(kept.begin(), kept.end(),
                            [&](const Refined& k) {
                              return k.history.inside >= config_.history.min_points &&
                                     k.history.inlierRatio() <
                                         best_history - config_.history_inlier_margin;
                            }),
             kept.end());
  // A placement that lays the remembered walls off the sketch (fewer than history.min_points of
  // them inside its extent) escapes the share tests. It is no rival to a reported or dormant
  // hypothesis that lays them onto the sketch's walls: on the 495 m cave with a partial sketch,
  // flying into the part the drawing left out made the true placement (600 of 600 remembered
  // walls inside, all explained) fail the window's fitness, and placements 430 m off, with 15-42
  // of the 600 inside, were reported instead for 35 s.
  const auto explains = [&](const HistoryFit& f) {
    return f.inside >= config_.history.min_points &&
           f.inlierRatio() >= config_.history_min_inlier_ratio;
  };
  // Among this frame's confirmed fits, best_history (above) already says whether one explains.
  const bool history_explained =
      use_history && (best_history >= config_.history_min_inlier_ratio ||
                      std::any_of(live_.begin(), live_.end(),
                                  [&](const Hypothesis& h) {
                                    return h.age_frames >= config_.confirm_frames &&
                                           explains(historyFit(h.T_world_sketch));
                                  }) ||
                      std::any_of(dormant_.begin(), dormant_.end(), [&](const Dormant& d) {
                        return explains(historyFit(d.h.T_world_sketch));
                      }));
  if (history_explained) {
    kept.erase(std::remove_if(kept.begin(), kept.end(),
                              [&](const Refined& k) {
                                return k.history.points >= config_.history.min_points &&
                                       k.history.inside < config_.history.min_points;
                              }),
               kept.end());
  }
  if (static_cast<int>(kept.size()) > config_.max_hypotheses) {
    kept.resize(static_cast<size_t>(config_.max_hypotheses));
  }
  // Reported hypotheses that failed go dormant; dormant ones that passed are live again, the
  // others count a miss and are dropped after dormant_frames.
  std::vector<Hypothesis> previous = std::move(live_);
  live_.clear();
  // Passed: refined and kept under its id, or merged into a kept one (which tracks it now).
  const auto passed = [&](const Hypothesis& h) {
    return std::any_of(kept.begin(), kept.end(), [&](const Refined& k) {
      return (k.id && *k.id == h.id) ||
             transformDistance(k.r.T_world_sketch, h.T_world_sketch, config_.verifier.lambda) <
                 config_.merge_distance;
    });
  };
  std::vector<Dormant> dormant;
  for (Dormant& d : dormant_)
    if (!passed(d.h) && ++d.misses <= config_.dormant_frames) dormant.push_back(d);
  for (const Hypothesis& h : previous)
    if (h.age_frames >= config_.confirm_frames && !passed(h) && config_.dormant_frames > 0)
      dormant.push_back({h, 1});
  dormant_ = std::move(dormant);
  for (Refined& k : kept) {
    Hypothesis h;
    h.id = k.id ? *k.id : next_id_++;
    h.T_world_sketch = k.r.T_world_sketch;
    h.fitness_m = k.r.fitness_m;
    h.inlier_ratio = k.r.inlierRatio();
    h.coverage = k.r.coverage;
    h.history = k.history;
    h.age_frames = k.age + 1;
    live_.push_back(h);
  }
}

}  // namespace efs::registration
