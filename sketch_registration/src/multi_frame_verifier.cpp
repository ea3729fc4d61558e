// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/multi_frame_verifier.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "efs_common/angles.h"
#include "efs_common/config_check.h"
#include "sketch_registration/dbscan.h"

namespace efs::registration {

void VerifierConfig::validate() const {
  requirePositive("scale_guess", scale_guess);
  requireInRange("scale_tolerance_factor", scale_tolerance_factor, 1.0, 1e3);
  requireInRange("triplet_scale_consistency", triplet_scale_consistency, 0.0, 10.0);
  requireInRange("candidate_position_error_m", candidate_position_error_m, 0.0, 1e3);
  requirePositive("match_radius_m", match_radius_m);
  requireInRange("match_radius_rel", match_radius_rel, 0.0, 10.0);
  requireInRange("min_anchor_displacement_m", min_anchor_displacement_m, 0.0, 1e4);
  requirePositive("fd_threshold", fd_threshold);
  requirePositive("max_relative_residual", max_relative_residual);
  requireInRange("yaw_tolerance_rad", yaw_tolerance_rad, 0.0, M_PI);
  requireInRange("lambda_t", lambda.lambda_t, 0.0, 1e6);
  requireInRange("lambda_r", lambda.lambda_r, 0.0, 1e6);
  requireInRange("lambda_s", lambda.lambda_s, 0.0, 1e6);
  requirePositive("dbscan_eps", dbscan_eps);
  requireInRange("dbscan_min_points", dbscan_min_points, 1, 1000);
  requireInRange("n_f", n_f, 3, 1000);
  requireInRange("max_dormant_frames", max_dormant_frames, 0, 100);
  requireInRange("max_tracks", max_tracks, 1, 10000000);
  requireInRange("max_cluster_input", max_cluster_input, 1, 100000);
}

MultiFrameVerifier::MultiFrameVerifier(const VerifierConfig& config)
    : config_(config), rng_(config.seed) {
  config_.validate();
}

void MultiFrameVerifier::reset() {
  reseed_requested_ = false;
  frames_.clear();
  tracks_.clear();
  representatives_.clear();
  stats_ = {};
  rng_.seed(config_.seed);
}

bool MultiFrameVerifier::scaleOk(double s) const {
  const double f = config_.scale_tolerance_factor;
  return s >= config_.scale_guess / f && s <= config_.scale_guess * f;
}

bool MultiFrameVerifier::pairScaleAgrees(double s, double dp, double dc) const {
  const double e = 2.0 * config_.candidate_position_error_m;
  const double k = config_.triplet_scale_consistency;
  const double s_min = dp / (dc + e) * (1.0 - k);
  // A pair whose candidates may lie at one place gives no upper bound.
  if (dc <= e) return s >= s_min;
  return s >= s_min && s <= dp / (dc - e) * (1.0 + k);
}

bool MultiFrameVerifier::yawOk(const Candidate& c, const Sim2& T) const {
  if (config_.yaw_tolerance_rad <= 0.0) return true;
  return c.reflected == T.reflected &&
         std::abs(angleDiff(c.yaw_rad, T.yaw_rad)) <= config_.yaw_tolerance_rad;
}

namespace {

Points2d mirrored(const Points2d& pts, bool reflect) {
  if (!reflect) return pts;
  Points2d out(pts);
  for (auto& p : out) p.y() = -p.y();
  return out;
}

double spread(const Points2d& pts) {
  Eigen::Vector2d m = Eigen::Vector2d::Zero();
  for (const auto& p : pts) m += p;
  m /= static_cast<double>(pts.size());
  double s = 0.0;
  for (const auto& p : pts) s += (p - m).squaredNorm();
  return std::sqrt(s / static_cast<double>(pts.size()));
}

/// Two-point similarity mapping c1 -> p1, c2 -> p2 (exact), with the given handedness.
Sim2 twoPoint(const Eigen::Vector2d& c1, const Eigen::Vector2d& c2, const Eigen::Vector2d& p1,
              const Eigen::Vector2d& p2, bool reflected) {
  Eigen::Vector2d dc = c2 - c1;
  if (reflected) dc.y() = -dc.y();
  const Eigen::Vector2d dp = p2 - p1;
  const double yaw = std::atan2(dp.y(), dp.x()) - std::atan2(dc.y(), dc.x());
  const double s = dp.norm() / dc.norm();
  Sim2 T(yaw, s, Eigen::Vector2d::Zero(), reflected);
  T.t_m = p1 - T.linear() * c1;
  return T;
}

}  // namespace

bool MultiFrameVerifier::evaluateTrack(Track& t) const {
  const Sim2Fit fit = fitSim2(t.c_sketch, t.p_world, t.T_world_sketch.reflected);
  if (!fit.ok || !scaleOk(fit.T_world_sketch.scale)) return false;
  const double sp = spread(t.p_world);
  if (!(sp > 1e-6)) return false;
  t.relative_residual = fit.rms_residual_m / sp;
  if (t.relative_residual > config_.max_relative_residual) return false;
  t.fd_distance =
      fourierDistance(fourierDescriptor(mirrored(t.c_sketch, fit.T_world_sketch.reflected)),
                      fourierDescriptor(t.p_world));
  if (t.fd_distance > config_.fd_threshold) return false;
  t.T_world_sketch = fit.T_world_sketch;
  return true;
}

void MultiFrameVerifier::getPotTran(int fa, int fb, int fc) {
  std::vector<int> idx = {fa, fb, fc};
  std::sort(idx.begin(), idx.end(), [&](int a, int b) {
    return frames_[static_cast<size_t>(a)].candidates.size() <
           frames_[static_cast<size_t>(b)].candidates.size();
  });
  const Frame& f1 = frames_[static_cast<size_t>(idx[0])];
  const Frame& f2 = frames_[static_cast<size_t>(idx[1])];
  const Frame& f3 = frames_[static_cast<size_t>(idx[2])];
  const double dp = (f1.p_world - f2.p_world).norm();
  if (dp < config_.min_anchor_displacement_m) return;
  const int hands = config_.allow_reflection ? 2 : 1;
  Track t;
  for (const Candidate& a : f1.candidates) {
    for (const Candidate& b : f2.candidates) {
      ++stats_.anchor_pairs;
      const double dc = (a.c_sketch - b.c_sketch).norm();
      if (!(dc > 1e-6)) continue;
      const double s_pair = dp / dc;
      if (!scaleOk(s_pair)) continue;
      ++stats_.pairs_scale_ok;
      for (int h = 0; h < hands; ++h) {
        const bool reflected = h == 1;
        const Sim2 T2 = twoPoint(a.c_sketch, b.c_sketch, f1.p_world, f2.p_world, reflected);
        const Eigen::Vector2d pred = T2.inverse().apply(f3.p_world);
        const double reach = std::min((pred - a.c_sketch).norm(), (pred - b.c_sketch).norm());
        const double r = config_.match_radius_m + config_.match_radius_rel * reach;
        for (const Candidate& c : f3.candidates) {
          if ((c.c_sketch - pred).squaredNorm() > r * r) continue;
          ++stats_.triplets_tested;
          t.c_sketch = {a.c_sketch, b.c_sketch, c.c_sketch};
          t.p_world = {f1.p_world, f2.p_world, f3.p_world};
          t.frames = {idx[0], idx[1], idx[2]};
          t.T_world_sketch = Sim2(0.0, 1.0, Eigen::Vector2d::Zero(), reflected);
          t.misses = 0;
          if (!evaluateTrack(t)) continue;
          if (!pairScaleAgrees(t.T_world_sketch.scale, dp, dc)) continue;
          t.yaw_consistent =
              yawOk(a, t.T_world_sketch) + yawOk(b, t.T_world_sketch) + yawOk(c, t.T_world_sketch);
          if (t.yaw_consistent < 2) continue;
          ++stats_.triplets_accepted;
          tracks_.push_back(t);
        }
      }
    }
  }
}

void MultiFrameVerifier::updateTracks(int frame) {
  const Frame& f = frames_[static_cast<size_t>(frame)];
  std::vector<Track> kept;
  kept.reserve(tracks_.size());
  for (Track& t : tracks_) {
    const Eigen::Vector2d pred = t.T_world_sketch.inverse().apply(f.p_world);
    const double reach = (pred - t.c_sketch.back()).norm();
    const double r = config_.match_radius_m + config_.match_radius_rel * reach;
    const Candidate* best = nullptr;
    double best_d2 = r * r;
    for (const Candidate& c : f.candidates) {
      const double d2 = (c.c_sketch - pred).squaredNorm();
      if (d2 <= best_d2) {
        best_d2 = d2;
        best = &c;
      }
    }
    bool matched = false;
    if (best) {
      Track u = t;
      u.frames.push_back(frame);
      u.c_sketch.push_back(best->c_sketch);
      u.p_world.push_back(f.p_world);
      if (evaluateTrack(u)) {
        u.misses = 0;
        u.yaw_consistent += yawOk(*best, u.T_world_sketch);
        kept.push_back(std::move(u));
        matched = true;
      }
    }
    if (!matched && ++t.misses <= config_.max_dormant_frames) kept.push_back(std::move(t));
  }
  tracks_ = std::move(kept);
}

void MultiFrameVerifier::cluster() {
  representatives_.clear();
  // Best first: more correspondences, fewer misses, better shape agreement.
  std::sort(tracks_.begin(), tracks_.end(), [](const Track& a, const Track& b) {
    if (a.frames.size() != b.frames.size()) return a.frames.size() > b.frames.size();
    if (a.misses != b.misses) return a.misses < b.misses;
    return a.fd_distance + a.relative_residual < b.fd_distance + b.relative_residual;
  });
  if (static_cast<int>(tracks_.size()) > config_.max_tracks) {
    tracks_.resize(static_cast<size_t>(config_.max_tracks));
  }
  const size_t n = std::min(tracks_.size(), static_cast<size_t>(config_.max_cluster_input));
  // DBSCAN only asks whether a pair lies within eps: a pair whose lower bound is beyond it (with
  // a margin for rounding) answers without the full distance.
  const TransformDistanceWeights& w = config_.lambda;
  const double eps = config_.dbscan_eps;
  const std::vector<int> label =
      dbscan(n, eps, static_cast<size_t>(config_.dbscan_min_points), [&](size_t i, size_t j) {
        const Sim2& a = tracks_[i].T_world_sketch;
        const Sim2& b = tracks_[j].T_world_sketch;
        if (transformDistanceLowerBound(a, b, w) > eps * (1.0 + 1e-9))
          return std::numeric_limits<double>::infinity();
        return transformDistance(a, b, w);
      });
  int num_clusters = 0;
  for (int l : label) num_clusters = std::max(num_clusters, l + 1);
  std::vector<int> best(static_cast<size_t>(num_clusters), -1), size(best.size(), 0);
  for (size_t i = 0; i < n; ++i) {
    if (label[i] < 0) continue;
    const size_t l = static_cast<size_t>(label[i]);
    ++size[l];
    // Tracks are sorted, so the first member has the most support; ties go to the best FD.
    if (best[l] < 0) best[l] = static_cast<int>(i);
  }
  for (size_t l = 0; l < best.size(); ++l) {
    if (best[l] < 0) continue;
    const Track& t = tracks_[static_cast<size_t>(best[l])];
    representatives_.push_back(
        {t.T_world_sketch, size[l], static_cast<int>(t.frames.size()), t.fd_distance});
  }
  std::stable_sort(representatives_.begin(), representatives_.end(),
                   [](const Representative& a, const Representative& b) {
                     if (a.num_correspondences != b.num_correspondences) {
                       return a.num_correspondences > b.num_correspondences;
                     }
                     return a.cluster_size > b.cluster_size;
                   });
  stats_.tracks = tracks_.size();
  stats_.representatives = representatives_.size();
}

bool MultiFrameVerifier::addFrame(const Eigen::Vector2d& p_world,
                                  const std::vector<Candidate>& candidates) {
  if (!p_world.allFinite() || candidates.empty()) return false;
  if (!frames_.empty() &&
      (p_world - frames_.back().p_world).norm() < config_.min_anchor_displacement_m) {
    return false;
  }
  stats_ = {};
  frames_.push_back({p_world, candidates});
  const int m = static_cast<int>(frames_.size()) - 1;
  if (frames_.size() < 3) return true;
  if (frames_.size() == 3) {
    getPotTran(0, 1, 2);
  } else {
    updateTracks(m);
    if (static_cast<int>(frames_.size()) <= config_.n_f) {
      // Two random earlier frames with the current one: a failed single frame among the first
      // three cannot block registration for good.
      std::vector<int> earlier(static_cast<size_t>(m));
      for (int i = 0; i < m; ++i) earlier[static_cast<size_t>(i)] = i;
      std::shuffle(earlier.begin(), earlier.end(), rng_);
      getPotTran(earlier[0], earlier[1], m);
    } else if ((tracks_.empty() && config_.reseed_when_empty) || reseed_requested_) {
      getPotTran(m - 2, m - 1, m);
    }
    reseed_requested_ = false;
  }
  cluster();
  return true;
}

}  // namespace efs::registration
