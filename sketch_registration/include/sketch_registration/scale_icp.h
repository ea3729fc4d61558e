// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Scale-ICP (paper Sec. V-C; bounded-scale ICP after Ying et al. 2009): refines a sketch->world
// similarity against the boundary of the observation map projected to 2D, and scores it with the
// fitness F = mean world-frame distance between matched points.
//
// Correspondences are searched from the observation into the sketch (a kd-tree over the sketch
// points): the observation is local while the sketch is global, so this direction pairs every
// observed wall with its sketch wall and leaves unobserved parts of the sketch out. Observed
// points that fall outside the sketch's extent (a partial sketch) are ignored. Correspondences are
// trimmed (the worst fraction and those beyond an annealed distance are dropped) and the scale is
// bounded, both overall and per iteration. Optionally a bounded stretch is refined too (a drawing
// whose aspect ratio is off, which no similarity fits over a large drawing).
#pragma once

#include <algorithm>
#include <memory>
#include <optional>
#include <vector>

#include "efs_common/nearest_point_grid.h"
#include "efs_common/point_kdtree.h"
#include "efs_common/sim2.h"
#include "sketch_registration/types.h"

namespace efs::registration {

struct IcpResult;

struct ScaleIcpConfig {
  int max_iterations = 60;
  int iteration_points = 400;         ///< observed points used while iterating (0 = all)
  double max_correspondence_m = 4.0;  ///< world, first iteration
  double min_correspondence_m = 1.0;  ///< world, annealed down to this
  double anneal_factor = 0.8;         ///< per iteration
  double trim_ratio = 0.95;           ///< keep this fraction of the closest pairs
  double scale_min = 0.4;             ///< world metres per sketch metre
  double scale_max = 2.5;
  double max_scale_step = 0.1;  ///< relative scale change per iteration
  /// Largest stretch (Sim2::stretch) refined: a drawing whose aspect ratio is off by up to this
  /// factor along some axis. 1 is the paper's similarity.
  double max_stretch = 1.0;
  double convergence_m = 1e-3;        ///< stop when the transform moves less than this
  double anneal_when_moved_m = 0.05;  ///< shrink the radius once a step moves less than this
  double fitness_trim_ratio = 0.8;    ///< F over this fraction of the closest observed points
  double inlier_distance_m = 1.0;     ///< for the inlier ratio
  double min_inlier_ratio = 0.75;     ///< below this the hypothesis is invalid
  /// How much lower the forward (observation -> sketch) inlier ratio may be than the inlier
  /// bound, for a fit whose reverse ratio (visible sketch -> observation) is at least
  /// slack_min_reverse_ratio. Walls the drawing leaves out (a partial sketch) are unexplained
  /// observed walls at the true placement, while every sketch wall in view lies on an observed
  /// one (small cave, partial: forward 0.55-0.74, reverse 0.96-1.0). A wrong placement on a
  /// repetitive floor can lay most sketch walls in view on observed ones too (office, one room
  /// off: forward 0.72, reverse 0.84), hence the high reverse gate. 0: both directions are held
  /// to the same bound.
  double forward_inlier_slack = 0.1;
  double slack_min_reverse_ratio = 0.95;
  double sketch_margin_m = 3.0;       ///< sketch frame, around the sketch's bounding box
  int min_points = 20;                ///< observed points inside the sketch needed
  bool reject_scale_at_bound = true;  ///< a refined scale pinned to scale_min/max is invalid
  /// Share of the observed points that must lie within the sketch's extent (bounding box +
  /// sketch_margin_m) for a valid fit: below it the transform laid the sketch somewhere else. A
  /// partial sketch covers less; a correct fit of one whose robot walked beyond the drawn part
  /// covers less still (IcpResult::inside_ratio).
  double min_inside_ratio = 0.3;
  /// Reverse term (the paper's direction, prior -> observation): sketch points visible from the
  /// robot within this world range must have an observed point nearby. Catches transforms that
  /// put sketch walls where the LiDAR saw free space. 0 disables.
  double reverse_range_m = 20.0;
  /// The reverse term only counts visible sketch points that lie within the observed area: no
  /// farther than reverse_extent_margin_m beyond the farthest observed point in their bearing
  /// (this many azimuth bins, a bin and its two neighbours). Far beyond it nothing was observed
  /// yet, or a wall the drawing misplaces (a deformed sketch) hides it; neither says the
  /// transform is wrong. 0 bins counts every visible sketch point.
  int reverse_extent_bins = 180;
  double reverse_extent_margin_m = 3.0;
  bool symmetric = false;  ///< also pair visible sketch points with observed ones while iterating
  /// Cold starts first try a small grid of yaw x scale offsets about the observation's centroid
  /// (ICP's own capture range in cluttered floors is a few degrees and percent): +-steps*step.
  int coarse_yaw_steps = 2;
  double coarse_yaw_step_rad = 0.0873;  ///< 5 deg
  int coarse_scale_steps = 2;
  double coarse_scale_step = 0.1;
  int coarse_points = 150;
  double coarse_truncation_m = 1.0;
  void validate() const;
  /// Whether a fit's inlier ratios pass `bound`: both directions `bound`, or the forward one
  /// `bound - forward_inlier_slack` where the reverse one reaches slack_min_reverse_ratio;
  /// without a reverse ratio, the forward one `bound`.
  bool inliersPass(const IcpResult& r, double bound) const;
};

/// What the reverse fitness term needs: the dense projected observation and the robot position.
struct ObservedIndex {
  const PointKdTree2d* tree = nullptr;  ///< dense 2D observation, world frame
  Eigen::Vector2d robot_world_m = Eigen::Vector2d::Zero();
};

struct IcpResult {
  Sim2 T_world_sketch;
  double fitness_m = 1e9;  ///< F: mean of the forward and (if available) reverse trimmed means
  double forward_inlier_ratio = 0.0;  ///< observed points within inlier_distance_m of the sketch
  /// Visible sketch points within inlier_distance_m of an observed one (when evaluated).
  std::optional<double> reverse_inlier_ratio;
  double forward_fitness_m = 1e9;  ///< observation -> sketch
  double reverse_fitness_m = 0.0;  ///< visible sketch -> observation (0 when not evaluated)
  /// Share of all observed points within inlier_distance_m of the mapped sketch, those outside
  /// the sketch's extent counted as unexplained.
  double coverage = 0.0;
  /// Share of the observed points within the sketch's extent (those the fit is judged on; with a
  /// drawing reach, those also within it of a sketch wall).
  double inside_ratio = 0.0;
  int iterations = 0;
  int num_points = 0;  ///< observed points used (those within the sketch's extent)
  /// usable, ScaleIcpConfig::inliersPass(min_inlier_ratio) and inside_ratio >= min_inside_ratio
  bool valid = false;
  /// At least min_points observed points inside the sketch and the scale not pinned: F, the
  /// inlier ratio and the coverage are computed (whatever the inside ratio; callers that hold a
  /// fit to another inside bound than min_inside_ratio check inside_ratio themselves).
  bool usable = false;
  bool scale_at_bound = false;  ///< refine() ended on scale_min or scale_max

  /// The smaller of the two directions' inlier ratios.
  double inlierRatio() const {
    return reverse_inlier_ratio ? std::min(forward_inlier_ratio, *reverse_inlier_ratio)
                                : forward_inlier_ratio;
  }
};

/// How walls observed earlier (ObservationHistory::beyond) lie on the sketch mapped by a
/// transform.
struct HistoryFit {
  int points = 0;     ///< remembered points evaluated
  int inside = 0;     ///< of those, within the sketch's extent (bounding box + margin)
  int explained = 0;  ///< within inlier_distance_m of a mapped sketch wall
  /// explained / inside (1 without points inside).
  double inlierRatio() const { return inside > 0 ? double(explained) / inside : 1.0; }
};

/// Relative distance to scale_min / scale_max under which a refined scale counts as pinned.
constexpr double kScaleBoundTolerance = 0.01;

/// The sketch's walls for nearest-point queries, and a lower bound of the distance to them on a
/// coarse grid. Many correspondences of a wrong transform lie metres from any wall, where the
/// nearest-point grid hands the query to the k-d tree (about a third of a frame's Scale-ICP on
/// registration_bench's garage); a query whose bound already exceeds the distance that matters
/// (the capture radius, the coarse search's cap, the inlier distance) needs no search, and its
/// outcome is the same.
class SketchWalls {
 public:
  SketchWalls() = default;
  /// Indexes `points_m` over [box_min_m, box_max_m].
  SketchWalls(PointKdTree2d::Points points_m, const Eigen::Vector2d& box_min_m,
              const Eigen::Vector2d& box_max_m);

  const NearestPointGrid2d& nearest() const { return nearest_; }
  /// A lower bound (>= 0) of the distance from `q_m` to the nearest wall point; 0 outside the box.
  double clearanceAtLeast(const Eigen::Vector2d& q_m) const {
    const double fx = (q_m.x() - min_m_.x()) * inv_cell_;
    const double fy = (q_m.y() - min_m_.y()) * inv_cell_;
    // Written so that NaN fails too.
    if (!(fx >= 0.0 && fy >= 0.0 && fx < nx_ && fy < ny_)) return 0.0;
    return clearance_m_[static_cast<size_t>(fy) * static_cast<size_t>(nx_) +
                        static_cast<size_t>(fx)];
  }

 private:
  NearestPointGrid2d nearest_;
  Eigen::Vector2d min_m_ = Eigen::Vector2d::Zero();
  double inv_cell_ = 1.0;
  double nx_ = 0.0, ny_ = 0.0;      ///< cell counts, as doubles for the range test
  std::vector<float> clearance_m_;  ///< per cell, rounded down
};

class ScaleIcp {
 public:
  /// The sketch's walls indexed for nearest-point queries over their extent + `margin_m`
  /// (non-finite points dropped).
  using SketchIndex = std::shared_ptr<const SketchWalls>;
  static SketchIndex indexSketch(const Points2d& sketch_points_m, double margin_m);

  ScaleIcp(const Points2d& sketch_points_m, const ScaleIcpConfig& config);
  /// Shares another refinement's index of the same sketch (building one takes ~0.1-0.3 s on a
  /// paper-size garage).
  ScaleIcp(SketchIndex sketch, const ScaleIcpConfig& config);

  /// Iterates from `T_init` on `observed_world_m` (2D boundary of the observation map).
  /// `start_correspondence_m` > 0 overrides max_correspondence_m (a warm start from last frame's
  /// refined transform needs no wide capture radius).
  IcpResult refine(const Sim2& T_init, const Points2d& observed_world_m,
                   double start_correspondence_m = 0.0,
                   const ObservedIndex* reverse = nullptr) const;
  /// Only the fitness of `T` (no iterations). `drawing_reach_m` > 0: observed points farther
  /// than this (world metres) from every mapped sketch wall lie beyond the drawing and are
  /// treated as those outside its extent are (not judged, unexplained in the coverage). Inside a
  /// partial drawing's extent the robot sees passages it leaves out: their walls, metres from any
  /// drawn one, say nothing about whether T lays the drawing where it belongs.
  IcpResult evaluate(const Sim2& T, const Points2d& observed_world_m,
                     const ObservedIndex* reverse = nullptr, double drawing_reach_m = 0.0) const;

  /// See HistoryFit.
  HistoryFit historyFit(const Sim2& T, const Points2d& remembered_world_m) const;

  const ScaleIcpConfig& config() const { return config_; }
  size_t numSketchPoints() const { return sketch_->nearest().size(); }
  const SketchIndex& sketchIndex() const { return sketch_; }

 private:
  Sim2 coarseSearch(const Sim2& T0, const Points2d& observed, const ObservedIndex* reverse) const;
  /// Sketch points visible from the robot under T, within reverse_range_m.
  Points2d visibleSketch(const Sim2& T, const Eigen::Vector2d& robot_world_m) const;
  ScaleIcpConfig config_;
  SketchIndex sketch_;
  Eigen::Vector2d box_min_, box_max_;  ///< queries outside are not matched (sketch extent + margin)
};

}  // namespace efs::registration
