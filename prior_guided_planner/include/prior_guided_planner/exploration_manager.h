// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The exploration "brain" as one stateful object (paper Algorithm 2 around its planning cycle):
// registered scans go into the observation map and the occupancy; on update() the frontier
// clusters and viewpoints are brought up to date and, when a replan is due, the hierarchical
// planner picks the local tour whose first viewpoint becomes the target. The ROS node and the
// in-process closed-loop mission both drive this class; it never reads a clock (time_s is
// injected) and holds no global state.
//
// Replanning happens when no plan exists yet, `replan_period_s` has elapsed, the target was
// reached (within `target_reached_m`), the target viewpoint disappeared (its frontier was
// observed), or new hypotheses arrived. A reached viewpoint is not planned for again (its id is
// remembered), nor is a cluster mostly made of the cells its cluster had (a re-sampled cluster
// gets new ids), so the robot never circles a frontier the scans cannot clear. A far target is
// handed on in stages along its searched path (max_goal_distance_m), the next stage planned once
// the robot is half-way to the current one. kFinished when no viewpoint remains, or when the only
// ones left were given up or are last resorts that stopped paying (last_resort_stall), and that
// held finish_confirmation_s with new scans meanwhile: a viewpoint set aside unreachable_attempts
// times (no progress toward it, the local planner found no way, the path search found none) is
// not planned for again. Set-aside viewpoints come back after unreachable_retry_s, or at once
// when nothing else is left, so a flight never hovers for ever in front of viewpoints it cannot
// reach (seen: the ROS planner retrying five viewpoints every minute until the test's time ran
// out). kStuck is transient: it says the planner found nothing to send this cycle and will look
// again on the next update.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <unordered_set>
#include <vector>

#include "prior_guided_planner/frontier_clusters.h"
#include "prior_guided_planner/hierarchical_planner.h"
#include "prior_guided_planner/observation_map.h"
#include "prior_guided_planner/occupancy_map.h"
#include "prior_guided_planner/openings.h"
#include "prior_guided_planner/path_length.h"
#include "prior_guided_planner/stall_watch.h"
#include "prior_guided_planner/viewpoint_sampler.h"

namespace efs::planner {

struct ExplorationManagerConfig {
  ObservationMapConfig observation;
  OccupancyConfig occupancy;
  FrontierClusterConfig frontier;
  ViewpointConfig viewpoint;
  LidarFovConfig fov;
  PathSearchConfig path;
  HierarchicalPlannerConfig planner;
  /// Free-space frontiers (openings.h), toured as openings_stay_in_tour below says; their cells
  /// are kept scan by scan (opening_cells.h).
  bool use_openings = true;
  OpeningConfig openings;
  /// When no surface viewpoint lies within this horizontal range of the robot, the openings
  /// within it are planned too, before the robot leaves for the far viewpoints [m]. A door the
  /// robot stands next to shows the LiDAR a cone of the room behind it, seen from close and so
  /// well observed: the room keeps no surface viewpoint and was only an opening, toured once
  /// nothing else was left (seen: a guided flight turning round 1.5 m from the door of the last
  /// room of the small indoor world, then crossing the building back to it at the end). 0: off,
  /// the default: in a 500 m cave it made both flights slower (guided 430.7 -> 479.4 s,
  /// prior-free 487.6 -> 601.4 s), in the paper-size building too (guided 671.5 -> 689.9 s,
  /// prior-free 571.9 -> 584.0 s); 8 m mended only that small-indoor flight (84.5 -> 78.0 s).
  double near_openings_radius_m = 0.0;
  /// ... and only those of at least this many cells: a door to an unseen room borders the
  /// unknown with the whole cone the LiDAR saw through it (247 cells at the small indoor
  /// world's last room), the shadow of a car or a pillar in the open with a few (6 to 42 in the
  /// small garage, where touring them made the flight 32 % longer).
  int near_openings_min_cells = 100;
  /// Once openings joined a tour (no surface viewpoint was left), every later plan tours them
  /// beside the surface viewpoints until none is found. Joining only while no surface viewpoint
  /// is left let far looks that add a few poorly observed cells pull them out again: a guided
  /// SubT-scale flight turned back and forth three times in 20 s between the last surface
  /// viewpoints in the west and openings 20-25 m north-east. Staying made every method faster
  /// on the quick tier (README, Benchmarks); false restores the plan-by-plan membership.
  /// A flight's first plan, over the map of one scan, has no surface viewpoint yet, so the
  /// openings are in the tours from the start (found at stop 39; joining only once surface
  /// viewpoints had been planned and ran out was slower on most quick-tier cells).
  bool openings_stay_in_tour = true;
  /// A reached opening is looked at again, once nothing else is left, when its viewpoint has
  /// moved on from where it was reached (ReachedOpeningsConfig). An opening keeps its id (its
  /// smallest cell) as it grows, and one that stays where it was reached is a dead end; but a
  /// door looked through in passing grows into the room behind it: seen in the small indoor
  /// world, an opening reached at the door (the vehicle turned away at once) was 292 cells
  /// with its viewpoint 6 m inside the room when the flight ended "exploration complete" at
  /// 89 % coverage, that room never entered.
  ReachedOpeningsConfig reached_openings;
  /// A plan that finds nothing but its last resorts (reached openings that moved on, pockets
  /// the sketch vouches for) finds no viewpoint instead once the well-observed surface cells
  /// have not grown by last_resort_min_gain_fraction in the last last_resort_patience_s
  /// (stall_watch.h), and the exploration ends as when none remains. Viewpoints set aside and
  /// retried early are not last resorts.
  StallConfig last_resort_stall;
  /// Plan at most this often [s] unless the target is reached, gone, or hypotheses changed.
  double replan_period_s = 1.0;
  /// The target counts as reached when the robot is this close to it [m].
  double target_reached_m = 1.0;
  /// The searched path length to the target viewpoint must shrink by target_progress_m within
  /// target_progress_timeout_s, or the target is set aside as unreachable for
  /// unreachable_retry_s. The global search and the local planner disagree at times (a gap
  /// the lattice passes that the vehicle's clearance does not: seen in ed21 and the garage,
  /// the vehicle hovering for minutes in front of a viewpoint the local planner found no path
  /// to). Then the next viewpoint gets its turn; the map may have changed when it comes back.
  double target_progress_m = 0.5;
  double target_progress_timeout_s = 10.0;
  double unreachable_retry_s = 60.0;
  /// "No viewpoint remains" ends the exploration only once it has held this long [s], with new
  /// scans inserted meanwhile; until then the target stays unset and every update plans again.
  /// One map can sit between two ways on: the frontiers of a passage observed, the opening
  /// beyond it not yet min_cells large. Seen in CI: rostest.mission_lio_dropout (small cave)
  /// "finished" 10 s into a flight the same launch files end at 98 % after 25-37 s. 0: the
  /// first such plan finishes.
  double finish_confirmation_s = 1.0;
  /// A viewpoint set aside this many times is given up for good (counted in
  /// ExplorationInputStats::viewpoints_given_up and named when the exploration finishes).
  int unreachable_attempts = 2;
  /// When the path search reaches no viewpoint from the robot, the robot's paths are searched
  /// again on a lattice this many times finer (path.search_resolution_m / factor). A 0.6 m
  /// lattice found no way out of an ed21 room through a corridor mouth 1.0-1.1 m wide that the
  /// 0.3 m occupancy leaves one or two cells wide; all 21 viewpoints were "unreachable" twice
  /// within 0.2 s, given up, and the flight finished at 78 % coverage. A 0.3 m lattice finds
  /// the way. 1: off.
  int fine_path_resolution_factor = 2;
  /// When the local planner gives up on the goal of a viewpoint this close to the vehicle [m],
  /// the viewpoint counts as reached instead of set aside: the vehicle is as near as it can get,
  /// and what it can see from there it has seen. Seen in a 500 m cave: viewpoints 2-2.7 m below
  /// and up to 2 m beside the vehicle (3.3 m away), over a floor the LiDAR cannot see from above
  /// (the local planner does not descend through unknown space); set aside and retried 60 s
  /// later, one drew the guided flight 80 m back. 0: always set aside.
  double unreachable_near_m = 4.0;
  /// A frontier cluster at least looked_at_fraction of whose cells belonged to the cluster of a
  /// reached viewpoint gets no viewpoint planned: the vehicle stood where it should have seen
  /// them well, and did not. A re-sampled cluster gets new viewpoint ids, so remembering the
  /// reached ids alone let the vehicle hover from one re-sample to the next (seen in the paper
  /// garage: floor patches beside pillars, 5-7 s at each). New frontier cells joining such a
  /// cluster make it a target again once they are the larger part. Cells leave the record when
  /// they stop being frontier. false: only the reached viewpoint ids are remembered.
  bool skip_looked_at_clusters = true;
  double looked_at_fraction = 0.5;
  /// A target viewpoint farther than this horizontally (or max_goal_climb_m vertically) is
  /// handed to the local planner in stages: the point of the searched path at that distance.
  /// The local planner sees a window around the robot only (minco_traj: 24 x 24 x 6 m); a goal
  /// beyond it was clamped into rock and searched for in vain (seen: 20 s hovering in a cave).
  double max_goal_distance_m = 8.0;
  double max_goal_climb_m = 2.0;
  /// The local planner's goal lies this far along the tour's searched path (robot, first
  /// viewpoint, next ones), within the reach above, instead of at the first viewpoint: the
  /// vehicle passes through viewpoints instead of stopping at each. A goal at the next viewpoint
  /// lay a median 2 m ahead in a 500 m cave (its frontier seen on the approach, the next one
  /// again 2 m away): the vehicle braked for every one and averaged 2 m/s of the 4 allowed,
  /// where EPIC follows its tour 10 m ahead. 0: the goal is the first viewpoint.
  double tour_lookahead_m = 8.0;
  /// Exploration box if known (guidepoints far outside it are ignored); std::nullopt = unknown.
  std::optional<Eigen::AlignedBox3d> bounds_world_m;
  /// Throws efs::ConfigError naming the key.
  void validate() const;
};

enum class ExplorationState { kWaitingForData, kExploring, kFinished, kStuck };
const char* toString(ExplorationState s);

/// Why a planning cycle ran (the first reason that applied, in this order). A flight that turns
/// round is read from these: a target that vanished before it was reached, against a periodic
/// plan that ordered the same viewpoints differently.
enum class ReplanReason {
  kFirstPlan,      ///< no plan yet
  kNewHypotheses,  ///< the registration's hypotheses changed
  kGoalRefused,    ///< the local planner gave up on the goal, or every goal was refused
  kNoProgress,     ///< target_progress_timeout_s passed without progress: target set aside
  kNoGoal,         ///< the last plan sent no goal
  kTargetReached,  ///< the robot came within target_reached_m of the target viewpoint
  kHalfWay,        ///< half-way to a goal short of the viewpoint (a stage, a look-ahead)
  kTargetGone,     ///< the target viewpoint is gone: its frontier was seen, or it became unsafe
  kPeriod,         ///< replan_period_s elapsed
};
const char* toString(ReplanReason r);

/// What reportGoalUnreachable made of a goal the local planner gave up on.
enum class GoalRefusal {
  kNotCurrent,      ///< not the current goal (or not finite): nothing changed
  kSetAside,        ///< its viewpoint is set aside for unreachable_retry_s
  kCountedReached,  ///< its viewpoint lies within unreachable_near_m: counted as reached
};
const char* toString(GoalRefusal r);

/// What the local trajectory planner gets.
struct ExplorationTarget {
  ExplorationState state = ExplorationState::kWaitingForData;
  bool has_goal = false;
  /// Where the local planner flies now: tour_lookahead_m along the tour's searched path, or the
  /// stage on the searched path to the next viewpoint when that is farther than
  /// max_goal_distance_m / max_goal_climb_m.
  Eigen::Vector3d goal_world_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d viewpoint_world_m = Eigen::Vector3d::Zero();  ///< next viewpoint position
  double goal_yaw_rad = 0.0;                                    ///< its yaw
  /// Where the sensor should face: the viewpoint's frontier cluster, or the staged goal in
  /// transit (the direction of travel).
  Eigen::Vector3d look_at_world_m = Eigen::Vector3d::Zero();
  std::optional<int> goal_viewpoint_id;
  std::vector<Eigen::Vector3d> tour_world_m;  ///< local tour (viewpoint positions) for display
  std::optional<int> active_hypothesis_id;
  BaselineMode mode_used = BaselineMode::kPriorFree;
  bool replanned = false;                                 ///< a new plan this update
  ReplanReason replan_reason = ReplanReason::kFirstPlan;  ///< why the last plan ran
  std::string message;  ///< why there is no goal, what input was refused, ...
};

/// Counters of refused input, for status messages and tests.
struct ExplorationInputStats {
  size_t scans_inserted = 0;
  size_t scans_empty = 0;
  size_t scans_rejected = 0;  ///< non-finite sensor origin
  size_t points_dropped_nonfinite = 0;
  size_t updates_rejected = 0;  ///< time going backwards or non-finite time / pose
  size_t hypotheses_rejected = 0;
  size_t goals_refused = 0;        ///< goals the local planner gave up on (reportGoalUnreachable)
  size_t goals_refused_near = 0;   ///< ... of them, near enough to count as reached
  size_t viewpoints_given_up = 0;  ///< set aside unreachable_attempts times: not planned again
};

class ExplorationManager {
 public:
  /// prior: guidepoints in the sketch frame; std::nullopt = no sketch (prior-free behaviour).
  /// Throws efs::ConfigError (config) or std::invalid_argument (malformed prior).
  ExplorationManager(const ExplorationManagerConfig& config, std::optional<GuidepointPrior> prior);

  /// One registered scan (world frame, like FAST-LIO2 cloud_registered) and the sensor origin.
  /// Non-finite points are dropped and counted; an empty scan is a no-op; a non-finite origin
  /// refuses the scan (counted, reported in the next target's message).
  void insertScan(const Eigen::Vector3d& sensor_origin_world_m,
                  const std::vector<Eigen::Vector3f>& points_world_m);

  /// Latest registration hypotheses (planner types; the caller converts). Replaces the previous
  /// set. Unusable ones (NaN, non-positive scale, bad confidence) are kept out and counted.
  void setHypotheses(std::vector<Hypothesis> hypotheses);

  /// The local planner gave up on `goal_world_m` (minco_traj: give_up_after_failed_plans). When
  /// that is the current goal, its viewpoint is set aside for unreachable_retry_s at once (the
  /// no-progress watchdog would wait target_progress_timeout_s), or counts as reached when it
  /// lies within unreachable_near_m of the vehicle's last update, and the next update() replans.
  /// A goal that is no longer the current one, or a non-finite one, changes nothing.
  GoalRefusal reportGoalUnreachable(const Eigen::Vector3d& goal_world_m, double time_s);

  /// Replans when due and returns the current target. time_s must not go backwards (else the
  /// update is refused with a message, no crash). Terminates (kFinished) when no viewpoint
  /// remains.
  const ExplorationTarget& update(double time_s, const RobotPose& robot);

  const ExplorationTarget& target() const { return target_; }
  const ObservationMap& observationMap() const { return observation_; }
  const OccupancyMap& occupancy() const { return occupancy_; }
  const FrontierClusterer& frontierClusters() const { return clusters_; }
  /// The last planning result (groups, sequences, attachments); nullptr before the first plan.
  const PlanningResult* lastPlan() const { return last_plan_ ? &*last_plan_ : nullptr; }
  /// Viewpoints of the last plan (indices match lastPlan()).
  const std::vector<PlanViewpoint>& viewpoints() const { return viewpoints_; }
  /// The usable hypotheses set last (those the next plan uses).
  const std::vector<Hypothesis>& hypotheses() const { return hypotheses_; }
  /// Attachment and guidepoint states under the hypothesis that guided the last plan; nullptr
  /// when none did (no prior, prior-free fallback, or a baseline without attachments).
  const HypothesisAttachment* activeAttachment() const;
  /// The selected prior sequence of the last plan as world positions (empty when none).
  std::vector<Eigen::Vector2d> activeGuidepointSequence() const;
  /// The guidepoints in the world of the last plan that had a guiding hypothesis, kept through
  /// plans without one (no viewpoint left) while hypotheses remain; with the predicted free
  /// space, where the openings the sketch vouches for are looked for (vouchingPlaces).
  std::vector<Eigen::Vector2d> guidingGuidepoints() const;
  /// Where the sketch vouches for unseen space, under the guiding hypothesis: its guidepoints and
  /// its predicted free samples (GuidepointPrior::predicted_free_sketch_m).
  std::vector<Eigen::Vector2d> vouchingPlaces() const;
  const std::optional<GuidepointPrior>& prior() const { return prior_; }
  const ExplorationInputStats& inputStats() const { return stats_; }
  const ExplorationManagerConfig& config() const { return config_; }

 private:
  void refreshMapProducts();
  /// The active hypothesis' place in the last plan's used_hypotheses and attachments.
  std::optional<size_t> activeUsedIndex() const;
  /// Appends the sketch-frame points mapped through guiding_T_world_sketch_ (none without one).
  void appendThroughGuide(const std::vector<Eigen::Vector2d>& sketch_m,
                          std::vector<Eigen::Vector2d>& world_m) const;
  /// Why a plan is due now; std::nullopt while the current target stands.
  std::optional<ReplanReason> replanDue(double time_s, const RobotPose& robot) const;
  void replan(double time_s, const RobotPose& robot);
  /// The goal for the local planner on the way from `from` to `viewpoint` (see
  /// max_goal_distance_m); the viewpoint itself when near enough or when no path is found.
  Eigen::Vector3d stagedGoal(const Eigen::Vector3d& from, const Eigen::Vector3d& viewpoint);
  /// The goal tour_lookahead_m along the searched path robot -> tour viewpoints (indices into
  /// viewpoints_), as far as it stays within reach; the first viewpoint when no path is known.
  Eigen::Vector3d tourGoal(const Eigen::Vector3d& from, const std::vector<int>& tour);
  /// The path search's path from the robot; on the fine lattice when the lattice finds none
  /// and a plan this cycle needed the fine one (robot_on_fine_lattice_).
  PathSearchResult searchFromRobot(const Eigen::Vector3d& from, const Eigen::Vector3d& to);
  bool withinGoalReach(const Eigen::Vector3d& from, const Eigen::Vector3d& to) const;
  /// Near a goal the local planner gave up on (reportGoalUnreachable), within its retry time.
  bool refusedGoal(const Eigen::Vector3d& goal_world_m) const;
  /// The target viewpoint (or opening) is not planned for again while it lives.
  void markTargetReached();
  /// Sets viewpoint `id` aside until time_s + unreachable_retry_s; gives it up on its
  /// unreachable_attempts-th time.
  void setAside(int id, double time_s);
  /// Set aside unreachable_attempts times: not planned for again.
  bool givenUp(int id) const;
  /// Whether at least looked_at_fraction of a cluster's cells are in looked_at_cells_.
  bool lookedAt(int cluster_id) const;

  ExplorationManagerConfig config_;
  std::optional<GuidepointPrior> prior_;
  ObservationMap observation_;
  OccupancyMap occupancy_;
  OpeningCellIndex opening_cells_;
  KnownColumns known_columns_;  ///< where the sketch's places are unseen (vouched openings)
  FrontierClusterer clusters_;
  ViewpointManager viewpoint_manager_;
  PathLengthCache path_cache_;
  /// The same search on a lattice fine_path_resolution_factor times finer, asked only when the
  /// lattice reaches no viewpoint from the robot (nullptr when the factor is 1).
  std::unique_ptr<PathSearch> fine_search_;
  bool robot_on_fine_lattice_ = false;
  HierarchicalPlanner planner_;

  std::vector<Hypothesis> hypotheses_;
  std::vector<Hypothesis> plan_hypotheses_;  ///< the set the last plan used
  bool hypotheses_changed_ = false;
  bool goal_refused_ = false;  ///< the local planner gave up on the current goal
  bool map_dirty_ = false;
  std::vector<PlanViewpoint> viewpoints_;
  std::vector<int> viewpoint_cluster_;  ///< cluster id per entry of viewpoints_
  std::vector<double> robot_len_;       ///< L(X_r, V) of the last plan per viewpoint
  std::set<int> reached_viewpoint_ids_;
  /// Frontier cells of the clusters of reached viewpoints (looked_at_fraction).
  std::unordered_set<VoxelKey, VoxelKeyHash> looked_at_cells_;
  OpeningTourMembership opening_membership_;
  ReachedOpenings reached_openings_;
  /// The well-observed count at each plan (last_resort_stall).
  StallWatch stall_;
  /// Set when the last resorts were given up (last_resort_stall), for the finish message.
  std::string stall_note_;
  std::map<int, Eigen::Vector3d> opening_look_at_;  ///< per opening viewpoint id
  /// Viewpoints (and openings) set aside as unreachable, until the time given [s].
  std::map<int, double> set_aside_until_s_;
  /// How often each viewpoint (or opening) was set aside; those set aside unreachable_attempts
  /// times are given up (kept for the whole flight: a few bytes per viewpoint that ever failed).
  std::map<int, int> set_aside_count_;
  /// Goal points the local planner gave up on, refused until the time given [s]; a goal within
  /// kRefusedGoalRadius_m of one is not sent (the same unreachable place, up to the robot's
  /// motion between plans).
  struct RefusedGoal {
    Eigen::Vector3d goal_world_m;
    double until_s;
  };
  static constexpr double kRefusedGoalRadius_m = 0.5;
  std::vector<RefusedGoal> refused_goals_;
  /// Since when, and after how many inserted scans, plans have found no viewpoint
  /// (finish_confirmation_s); unset while they find some.
  struct NothingLeft {
    double since_s;
    size_t scans_inserted;
  };
  std::optional<NothingLeft> nothing_left_;
  /// The hypothesis of the last plan that had a guiding one, kept while hypotheses remain
  /// (guidingGuidepoints, vouchingPlaces).
  std::optional<Sim2> guiding_T_world_sketch_;
  /// Progress toward the current target (target_progress_m).
  struct Progress {
    int viewpoint_id;
    double best_length_m;
    double since_s;
  };
  std::optional<Progress> progress_;
  /// Sets the target aside when the robot made no progress toward it; true if it did.
  bool checkProgress(double time_s);
  std::optional<PlanningResult> last_plan_;
  double goal_distance_at_plan_m_ = 0.0;  ///< robot to goal when the goal was set
  std::optional<double> last_time_s_;
  Eigen::Vector3d last_robot_world_m_ = Eigen::Vector3d::Zero();  ///< at the last update
  /// The robot's path since the target was set came within target_reached_m of its viewpoint,
  /// where it is now included (update() follows the path between updates; replan() consumes it).
  bool target_passed_ = false;
  std::optional<double> last_plan_time_s_;
  ExplorationTarget target_;
  ExplorationInputStats stats_;
  std::string plan_message_;     ///< what the last plan said
  std::string pending_message_;  ///< refused input since the last update
};

}  // namespace efs::planner
