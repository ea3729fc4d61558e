// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Multi-frame verification (paper Sec. V-B): per-frame candidate sets Q^i are combined into
// potential sketch->world transforms.
//   GetPotTran: the two frames with the fewest candidates are anchors; every anchor pair gives a
//     scale s~ = |p1 - p2| / |c1 - c2| that must agree with the scale guess; the pair's
//     two-point similarity predicts where the third frame's candidate must lie, and each third
//     candidate near it closes a triplet, solved in closed form (least squares on 3 points) and
//     kept if its scale agrees with s~ (this is the paper's enumeration of all triplets, with the
//     triplets that the scale test would reject never built).
//   FilterOutliers: with every new frame each potential transform looks for a candidate near its
//     prediction, is refit by least squares over all its correspondences and kept while the
//     Fourier descriptor of its sketch polygon matches that of the robot polygon; a transform
//     that finds nothing goes dormant for one frame and is dropped after a second miss.
//   Robustness (V-B-3): for frames 4..N_f, two random earlier frames with the current one seed new
//     triplets.
//   Transforms are clustered by DBSCAN with d_T; each cluster is represented by its member with
//     the best Fourier-descriptor agreement.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "efs_common/sim2.h"
#include "sketch_registration/candidate_database.h"
#include "sketch_registration/sim2_fit.h"

namespace efs::registration {

struct VerifierConfig {
  double scale_guess = 1.0;             ///< s_g: world metres per sketch metre
  double scale_tolerance_factor = 2.5;  ///< pair scales in [s_g / f, s_g * f] pass
  /// A triplet's scale may lie this share outside what the anchor pair allows (below).
  double triplet_scale_consistency = 0.35;
  /// How far a selected candidate may lie from the robot's place in the sketch (the d_gap grid,
  /// the downsampling): the anchor pair's scale s~ = |p1 - p2| / |c1 - c2| is then only known to
  /// lie in [|p1 - p2| / (|c1 - c2| + 2e), |p1 - p2| / (|c1 - c2| - 2e)], and a triplet's scale
  /// must agree with that interval rather than with s~. On the recorded cave flight, anchor
  /// candidates 1.4 and 3.2 sketch m apart on the 1 m grid put s~ 25 % below and 45 % above the
  /// true scale, and the true triplets were vetoed. 0: the paper's test against s~ alone.
  double candidate_position_error_m = 1.0;
  double match_radius_m = 4.0;     ///< sketch frame: d_cand = 4 d_gap
  double match_radius_rel = 0.25;  ///< + this times the distance to the nearest used candidate
  double min_anchor_displacement_m = 1.5;  ///< world: robot baseline below this gives no scale
  double fd_threshold = 0.25;              ///< Fourier-descriptor distance sketch vs robot polygon
  double max_relative_residual = 0.3;      ///< LS residual / robot-polygon spread
  double yaw_tolerance_rad = 0.7;          ///< candidate shift yaw vs transform yaw; 0 disables
  TransformDistanceWeights lambda;         ///< 5 / 10 / 1
  double dbscan_eps = 10.0;                ///< in d_T units
  int dbscan_min_points = 1;               ///< 1: singletons are clusters (few hypotheses early)
  int n_f = 4;                             ///< N_f
  int max_dormant_frames = 1;              ///< misses tolerated in a row
  int max_tracks = 4000;
  int max_cluster_input = 1500;   ///< DBSCAN is O(n^2): best tracks only
  bool allow_reflection = true;   ///< also build mirror-image transforms
  bool reseed_when_empty = true;  ///< after N_f, restart from the last three frames
  uint64_t seed = 1;
  void validate() const;
};

/// A potential transform with its correspondences (frame index, candidate position).
struct Track {
  Sim2 T_world_sketch;
  std::vector<int> frames;
  Points2d c_sketch;
  Points2d p_world;
  int misses = 0;
  double fd_distance = 0.0;
  double relative_residual = 0.0;
  int yaw_consistent = 0;  ///< correspondences whose shift yaw agrees with the transform
};

struct Representative {
  Sim2 T_world_sketch;
  int cluster_size = 0;
  int num_correspondences = 0;
  double fd_distance = 0.0;
};

struct VerifierStats {
  size_t anchor_pairs = 0;       ///< all anchor pairs
  size_t pairs_scale_ok = 0;     ///< passed the scale-guess filter
  size_t triplets_tested = 0;    ///< third candidates near the prediction
  size_t triplets_accepted = 0;  ///< scale, residual, yaw and FD filters passed
  size_t tracks = 0;
  size_t representatives = 0;
};

class MultiFrameVerifier {
 public:
  explicit MultiFrameVerifier(const VerifierConfig& config);

  /// Adds frame i (robot position, FindCand output). Returns false (frame ignored) when the
  /// robot moved less than min_anchor_displacement_m since the last frame or has no candidates.
  bool addFrame(const Eigen::Vector2d& p_world, const std::vector<Candidate>& candidates);

  size_t numFrames() const { return frames_.size(); }
  const std::vector<Track>& tracks() const { return tracks_; }
  const std::vector<Representative>& representatives() const { return representatives_; }
  const VerifierStats& lastStats() const { return stats_; }
  const VerifierConfig& config() const { return config_; }
  void reset();
  /// The next frame seeds new triplets from the last three frames even while tracks exist (the
  /// caller found that none of the current transforms survives the fitness test: a surviving
  /// wrong track would otherwise block the robustness restart for good).
  void requestReseed() { reseed_requested_ = true; }

 private:
  struct Frame {
    Eigen::Vector2d p_world;
    std::vector<Candidate> candidates;
  };
  void getPotTran(int fa, int fb, int fc);
  void updateTracks(int frame);
  bool evaluateTrack(Track& t) const;
  void cluster();
  bool scaleOk(double s) const;
  bool yawOk(const Candidate& c, const Sim2& T) const;
  bool pairScaleAgrees(double s, double dp, double dc) const;

  VerifierConfig config_;
  std::vector<Frame> frames_;
  std::vector<Track> tracks_;
  std::vector<Representative> representatives_;
  VerifierStats stats_;
  std::mt19937_64 rng_;
  bool reseed_requested_ = false;
};

}  // namespace efs::registration
