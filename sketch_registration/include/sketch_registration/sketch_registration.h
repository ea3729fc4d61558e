// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// SketchRegistration: the whole of the paper's Algorithm 1 behind one call per frame.
//   construction  = Phase 1 (HPR + GeoContext at every candidate location of the sketch);
//   addFrame()    = Phase 2 for one frame: HPR + GeoContext at the robot, FindCand, multi-frame
//                   verification, Scale-ICP of the surviving transforms, fitness threshold,
//                   confidence softmax, stable hypothesis ids.
// It takes plain types (sketch boundary points and candidate locations in the sketch's metric
// frame, the local map in the world frame) so that the ROS node and the evaluation tool stay thin.
// Time is injected; nothing here reads a clock.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "efs_common/sim2.h"
#include "sketch_registration/candidate_database.h"
#include "sketch_registration/geo_context.h"
#include "sketch_registration/multi_frame_verifier.h"
#include "sketch_registration/observation.h"
#include "sketch_registration/observation_history.h"
#include "sketch_registration/scale_icp.h"

namespace efs::registration {

/// How mirror-image sketches are handled. Matching the mirrored descriptor costs about twice the
/// shift search; without it a mirrored sketch finds no consistent triplet.
enum class ReflectionMode {
  kIgnore,    ///< proper transforms only
  kDetect,    ///< search reflected transforms too; report them apart, status kMirroredSketch
  kRegister,  ///< reflected transforms are ordinary hypotheses (Sim2::reflected = true)
};

enum class RegistrationStatus {
  kOk,                    ///< at least one hypothesis
  kTooFewFrames,          ///< fewer than three usable frames so far
  kNoConsistentTriplet,   ///< multi-frame verification left no potential transform
  kAllRejectedByFitness,  ///< Scale-ICP fitness above F_thresh for every transform
  kNoCandidates,          ///< the sketch has no usable candidate location
  kBadInput,              ///< this frame was unusable (empty / non-finite map, time, position)
  kOdometryJump,          ///< the robot jumped; the multi-frame state was restarted
  kMirroredSketch,        ///< only mirror-image transforms fit (kDetect mode)
  kAwaitingConfirmation,  ///< a new transform passed the fitness test; not yet on confirm_frames
};
const char* toString(RegistrationStatus status);

struct Hypothesis {
  int id = 0;  ///< assigned on creation (0, 1, 2, ...); stable while the hypothesis survives
  Sim2 T_world_sketch;
  double fitness_m = 0.0;  ///< F
  /// softmax(-tau (F + coverage_weight_m (1 - coverage))) over the reported hypotheses
  double confidence = 0.0;
  double inlier_ratio = 0.0;
  double coverage = 0.0;  ///< IcpResult::coverage of this frame's observation
  HistoryFit history;     ///< walls remembered beyond this frame's observation
  int age_frames =
      0;  ///< consecutive frames it passed the fitness test (reported from confirm_frames)
};

struct FrameDiagnostics {
  double time_s = 0.0;
  Eigen::Vector2d robot_world_m = Eigen::Vector2d::Zero();
  GeoContext descriptor;               ///< of the observation at the robot
  std::vector<Candidate> candidates;   ///< FindCand output of this frame
  bool used_for_verification = false;  ///< false: too close to the previous frame or no candidates
  VerifierStats verifier;
  size_t representatives = 0;
  size_t icp_runs = 0;
  size_t descriptor_points = 0;
  size_t icp_points = 0;
};

struct RegistrationResult {
  RegistrationStatus status = RegistrationStatus::kTooFewFrames;
  std::string message;
  std::vector<Hypothesis> hypotheses;           ///< best (highest confidence) first
  std::vector<Hypothesis> mirrored_hypotheses;  ///< kDetect: reflected fits kept apart
  bool best_is_mirrored = false;                ///< kRegister: the best hypothesis is reflected
  size_t frames_used = 0;                       ///< frames in the multi-frame verification
  FrameDiagnostics last_frame;
};

struct SketchRegistrationConfig {
  double d_gap_m = 1.0;                 ///< candidate spacing (for makeCandidateGrid callers)
  double scale_guess = 1.0;             ///< s_g: world metres per sketch metre
  double scale_tolerance_factor = 2.5;  ///< true scale within [s_g / f, s_g * f]
  /// With descriptor.clip_to_range, the sketch descriptors are cut at the observation's range
  /// limit for this many scales, geometric over [s_g / f, s_g * f]: the limit is in world metres
  /// and the scale unknown. Retrieval on the paper garage (true scale 1.64 s_g) stayed at
  /// 96-100 % with the cut 0.85-1.2 x the true one and fell to 63 % at 1.64 x; 7 levels are
  /// 1.36 x apart, so the nearest is at most 1.17 x off.
  int scale_levels = 7;
  DescriptorConfig descriptor;  ///< max_range_m / point_radius_m in world metres
  /// The angle a sketch point occludes and covers in the depth buffer (sketch metres). Thinning
  /// leaves gaps of up to twice boundary_spacing_m between points; with clip_to_range a fine bin
  /// left empty between two points of one wall reads the range limit. 0.1 (half the spacing):
  /// paper garage precise 87.5 % single-frame, indoor deformed 96.3 %; 0.15: 100 % and 97.8 %;
  /// 0.2: 95.8 % and 97.0 % (eta 5 %).
  double sketch_point_radius_m = 0.15;
  RetrievalConfig retrieval;  ///< eta, alphas, downsampling
  VerifierConfig verifier;    ///< its scale and reflection fields are set from here
  /// Its scale bounds are set from here. Its stretch is on (up to 1.1, judged by
  /// stretch_min_fitness_gain): the paper garage's drawing, stretched by up to 8 % along one axis
  /// against the other, registers with it and not without.
  ScaleIcpConfig icp = [] {
    ScaleIcpConfig c;
    c.max_stretch = 1.1;
    return c;
  }();
  ObservationConfig observation;
  ObservationHistoryConfig history;
  /// The joint (window + remembered walls) refinement replaces the window's own one unless it
  /// lowers the window's inlier ratio by more than this.
  double history_inlier_slack = 0.05;
  /// Once history.min_points remembered walls lie within the sketch's extent, a new hypothesis
  /// must lay this share of them onto sketch walls (HistoryFit::inlierRatio), a reported one
  /// history_kept_min_inlier_ratio. Wrong placements that fit the window lay 0-0.45 of them on
  /// walls (paper-size cave and garage), the truth 1.0 (cave, indoor) and 0.75-0.9 (garage).
  /// A hypothesis (reported, live or dormant) that passes this share also shuts out placements
  /// that leave fewer than history.min_points remembered walls inside the sketch.
  double history_min_inlier_ratio = 0.6;
  double history_kept_min_inlier_ratio = 0.45;
  /// A hypothesis whose HistoryFit::inlierRatio falls this far below the best reported one's is
  /// dropped.
  double history_inlier_margin = 0.1;
  double fitness_threshold_m = 0.6;  ///< F_thresh (not given in the paper)
  /// With icp.max_stretch > 1, a hypothesis (and a new transform whose similarity fit comes
  /// within 1.5 F_thresh) is refined both as a similarity and with a stretch, and keeps the
  /// stretch only where it lowers F by at least this share. On the 300 m SubT-scale cave a
  /// 0.5-1.5 % stretch fitted to the walls seen put the far sketch 1-2 m off for minutes
  /// (placement error 0.8-2 m against 0.1-0.4 m), at an F hardly lower.
  double stretch_min_fitness_gain = 0.25;
  /// Hysteresis: a hypothesis already reported survives while its F stays below this and its
  /// inlier ratio above kept_min_inlier_ratio; a new one must pass fitness_threshold_m and
  /// icp.min_inlier_ratio. Clutter and sketch deformation move a correct fit around the new-
  /// hypothesis bounds from frame to frame; a wrong transform rarely passes them in the first
  /// place.
  double kept_fitness_threshold_m = 0.8;
  double kept_min_inlier_ratio = 0.6;
  /// The same hysteresis for the share of the observation within the sketch's extent (a new
  /// hypothesis: icp.min_inside_ratio). Beyond a partial sketch the true placement's share falls
  /// with every metre walked while the walls inside still fit: an office drawn west of 30 m lost
  /// its true placement for 3 frames at 0.16-0.25 inside (F 0.03-0.04 m, inliers 0.86-0.89). 0:
  /// a reported hypothesis is judged on the observed walls inside the sketch alone (at least
  /// icp.min_points of them), by the kept F and inlier bounds.
  double kept_min_inside_ratio = 0.0;
  /// A reported hypothesis that fails the kept bounds on the whole window is judged again on the
  /// observed walls within this many world metres of a mapped sketch wall (ScaleIcp::evaluate's
  /// drawing reach); the rest count against its coverage, not its F. Flying through a passage a
  /// partial drawing leaves out, inside its extent, raised the true placement's F to 1.9-2.8 m
  /// (Pittsburgh mine, partial), while all 600 remembered walls inside lay on drawn ones; a
  /// wrong placement still lays half the walls near the drawing more than a metre off. 0: off.
  double kept_drawing_reach_m = 2.0;
  /// ... once it has passed this many consecutive frames. On a repetitive floor a placement one
  /// bay off fits the walls near the drawing as well as the truth: the paper garage's partial
  /// drawing had three such placements held 50 s longer by the reach, at ages 3-7 frames (F 0.09
  /// m, inliers 1.0 near the drawing, coverage 0.29-0.61), while the mine's true placement was
  /// rescued at ages 80-140 (registration_eval, 1800 s route).
  int kept_drawing_reach_min_age_frames = 12;
  /// Coverage (IcpResult::coverage) is the share of the observation a hypothesis explains, with
  /// observed walls beyond the sketch's extent unexplained. F alone does not tell a hand drawing
  /// laid shrunken on an office's repetitive walls from its true placement (ed21_1: F 0.27-0.54 m
  /// at scale 0.56-0.67, 0.28-0.48 m at the truth); coverage does (0.39-0.46 once the robot had
  /// seen more than the shrunken sketch spans, 0.68-0.78 at the truth).
  /// The verifier keeps seeding fresh triplets every frame until a hypothesis explains at least
  /// this share (0: only while no hypothesis survives).
  double settled_coverage = 0.8;
  /// Hypotheses are ranked, and their confidence taken, by F + this * (1 - coverage).
  double coverage_weight_m = 1.0;
  /// A new transform is reported once it passed the new-hypothesis bounds on this many
  /// consecutive frames (the looser kept bounds apply only after that). A wrong place can fit
  /// one frame's map well (seen: F 0.29 m for a sketch of another cave) but not the next one's.
  int confirm_frames = 2;
  /// A reported hypothesis that fails a frame is not dropped at once: it goes dormant (not
  /// reported, its transform kept) and is refined again, under the kept bounds, on each of the
  /// next dormant_frames frames; passing brings it back under its id (the paper's dormant
  /// solutions, Sec. V-B-3, for refined hypotheses). Seen on the 495 m cave: the true placement,
  /// held for 128 frames at F 0.15-0.17 m, was lost on one frame whose observation had 59 wall
  /// columns instead of ~500, and the verifier took 32 frames to find it again. 0: dropped at once.
  int dormant_frames = 12;
  double confidence_tau = 0.3;  ///< tau
  double max_speed_mps = 20.0;  ///< faster between frames = odometry jump
  ReflectionMode reflection = ReflectionMode::kDetect;
  int max_icp_inputs = 8;  ///< new representatives refined per frame
  /// With more new representatives than max_icp_inputs, which are refined: half in the
  /// verifier's order (most correspondences first), half the best of the rest after a short
  /// refinement (screen_iterations, no coarse search, no reverse term) on screen_points of the
  /// observation, by forward inlier share. The verifier's order alone favours the wrong tracks a
  /// repetitive floor keeps alive: on a flight through the paper-size garage the only
  /// representative that refined onto the truth ranked 79th-814th by correspondences and 1st-15th
  /// by this screen. The screen alone let a nearby wrong placement of a distorted hand drawing
  /// lead (ed21 sketch 3). 0: the verifier's order only.
  int screen_points = 64;
  int screen_iterations = 10;
  int icp_retry_frames = 3;       ///< a rejected transform waits this many frames (0: retried next)
  int mirror_min_age_frames = 2;  ///< kMirroredSketch only once a mirror fit has persisted
  /// In kDetect mode a persisted mirror-image fit whose coverage exceeds every proper fit's by
  /// this much makes the sketch mirrored: the proper fits, which explain only part of what was
  /// observed, are not reported (a mirrored office drawing: mirror fit coverage 1.0; proper fits
  /// shifted by a room on the repetitive floor, 0.49 and 0.31).
  double mirror_dominance_coverage = 0.3;
  int max_hypotheses = 10;
  double merge_distance = 10.0;  ///< d_T below which refined hypotheses are one
  void validate() const;
};

class SketchRegistration {
 public:
  using Config = SketchRegistrationConfig;

  /// Phase 1. `sketch_boundary_m`: the sketch's wall/boundary points; `candidates_m`: candidate
  /// locations on the d_gap grid of the traversable region (both in the sketch frame). Non-finite
  /// entries are dropped; an empty sketch or candidate set is allowed (status kNoCandidates).
  SketchRegistration(const Config& config, Points2d sketch_boundary_m, Points2d candidates_m);

  /// Phase 2 for one frame. `time_s` must increase; `robot_world_m` is the robot position and
  /// `local_map_world_m` the accumulated local map, both in the world (LIO) frame.
  const RegistrationResult& addFrame(double time_s, const Eigen::Vector3d& robot_world_m,
                                     const Points3d& local_map_world_m);

  const RegistrationResult& result() const { return result_; }
  const CandidateDatabase& database() const { return database_; }
  const MultiFrameVerifier& verifier() const { return verifier_; }
  const Config& config() const { return config_; }
  const Points2d& sketchBoundary() const { return sketch_; }
  const ObservationHistory& history() const { return history_; }
  /// How the remembered walls (beyond the last frame's observation) lie on the sketch mapped by
  /// `T_world_sketch` (what the hypotheses carry; diagnostics for any transform).
  HistoryFit historyFit(const Sim2& T_world_sketch) const;
  /// What the fitness test makes of `T_world_sketch` on the last frame's observation, as a new
  /// transform there would be judged before refinement (diagnostics against a known truth).
  /// Not usable (IcpResult::usable false) when the last frame was ignored (bad input).
  IcpResult evaluateOnLastFrame(const Sim2& T_world_sketch) const;
  /// The Scale-ICP refinement the hypotheses go through (diagnostics refine other transforms with
  /// it rather than index the sketch a second time).
  const ScaleIcp& refinement() const { return *icp_; }
  /// Forgets all frames and hypotheses (keeps Phase 1).
  void reset();

 private:
  void updateHypotheses(const Points2d& icp_points, const ObservedIndex& observed,
                        FrameDiagnostics& diag);
  /// The new representatives (not tracked by a live hypothesis, not waiting after a rejection)
  /// refined this frame: at most max_icp_inputs, chosen as screen_points says.
  std::vector<Sim2> newInputs(const Points2d& icp_points) const;
  RegistrationResult& fail(RegistrationStatus status, const std::string& message);
  /// The history is used once history.min_points remembered walls lie beyond the window.
  bool historyInUse() const;
  /// A live hypothesis' refinement: as a similarity, and with a stretch where that is on (see
  /// stretch_min_fitness_gain).
  IcpResult refineLive(const Sim2& T, const Points2d& points, double start_correspondence_m,
                       const ObservedIndex& observed) const;
  /// The refinement with a stretch from T if it lowers F by stretch_min_fitness_gain against
  /// `similarity`, else `similarity`.
  IcpResult stretchedIfBetter(const IcpResult& similarity, const Sim2& T, const Points2d& points,
                              double start_correspondence_m, const ObservedIndex& observed) const;

  Config config_;
  Points2d sketch_;
  CandidateDatabase database_;
  MultiFrameVerifier verifier_;
  std::unique_ptr<ScaleIcp> icp_;
  std::unique_ptr<ScaleIcp> screen_icp_;  ///< the short refinement of screen_points
  /// Refines with a stretch (icp.max_stretch); null while the stretch is off. icp_ and
  /// screen_icp_ fit similarities.
  std::unique_ptr<ScaleIcp> stretch_icp_;
  ObservationHistory history_;
  /// The last frame's observation as Scale-ICP reads it (evaluateOnLastFrame); empty when that
  /// frame was ignored.
  struct LastObservation {
    Points2d icp_points;
    PointKdTree2d dense;
    Eigen::Vector2d robot_world_m = Eigen::Vector2d::Zero();
  };
  std::optional<LastObservation> last_observation_;
  RegistrationResult result_;
  std::vector<Hypothesis> live_;  ///< all refined hypotheses (both handednesses)
  struct Dormant {
    Hypothesis h;
    int misses;  ///< consecutive frames it failed
  };
  std::vector<Dormant> dormant_;  ///< reported hypotheses that failed recently (dormant_frames)
  struct Rejected {
    Sim2 T;
    size_t frame;
  };
  std::vector<Rejected> rejected_;  ///< transforms that failed fitness recently (not retried yet)
  size_t frame_counter_ = 0;
  int next_id_ = 0;
  bool has_last_ = false;
  double last_time_s_ = 0.0;
  Eigen::Vector2d last_robot_m_ = Eigen::Vector2d::Zero();
};

/// Orders hypotheses best first by F + coverage_weight_m (1 - coverage) and sets their confidence
/// to the softmax of -tau times that (the paper's softmax(-tau F) when coverage_weight_m is 0).
void rankHypotheses(std::vector<Hypothesis>& hypotheses, double tau, double coverage_weight_m);

/// The per-module configs derived from the top-level one (sketch-frame descriptor range, scale
/// bounds, reflection); exposed so that tools reproduce exactly what the class uses.
DescriptorConfig sketchDescriptorConfig(const SketchRegistrationConfig& config);
/// The sketch-metre ranges at which the observation's range limit lies at each of scale_levels
/// scales, longest first (the first is sketchDescriptorConfig's max_range_m).
std::vector<double> sketchRangeLevelsM(const SketchRegistrationConfig& config);
DescriptorConfig observationDescriptorConfig(const SketchRegistrationConfig& config);
VerifierConfig verifierConfig(const SketchRegistrationConfig& config);
ScaleIcpConfig scaleIcpConfig(const SketchRegistrationConfig& config);
RetrievalConfig retrievalConfig(const SketchRegistrationConfig& config);

}  // namespace efs::registration
