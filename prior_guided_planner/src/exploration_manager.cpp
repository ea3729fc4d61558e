// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/exploration_manager.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include "efs_common/config_check.h"
#include "efs_common/segment_distance.h"
#include "prior_guided_planner/goal_along_path.h"
#include "prior_guided_planner/observation_map_inputs.h"

namespace efs::planner {

void ExplorationManagerConfig::validate() const {
  observation.validate();
  occupancy.validate();
  frontier.validate();
  viewpoint.validate();
  fov.validate();
  path.validate();
  planner.validate();
  openings.validate();
  reached_openings.validate();
  last_resort_stall.validate();
  requireInRange("replan_period_s", replan_period_s, 0.0, 3600.0);
  requireInRange("target_reached_m", target_reached_m, 1e-3, 1e3);
  requireInRange("target_progress_m", target_progress_m, 0.0, 1e3);
  requireInRange("target_progress_timeout_s", target_progress_timeout_s, 0.1, 1e6);
  requireInRange("finish_confirmation_s", finish_confirmation_s, 0.0, 600.0);
  requireInRange("unreachable_retry_s", unreachable_retry_s, 0.0, 1e6);
  requireInRange("unreachable_attempts", unreachable_attempts, 1, 1000);
  requireInRange("fine_path_resolution_factor", fine_path_resolution_factor, 1, 8);
  requireInRange("unreachable_near_m", unreachable_near_m, 0.0, 1e3);
  requireInRange("looked_at_fraction", looked_at_fraction, 0.01, 1.0);
  requireInRange("max_goal_distance_m", max_goal_distance_m, 1.0, 1e4);
  requireInRange("max_goal_climb_m", max_goal_climb_m, 0.5, 1e4);
  requireInRange("tour_lookahead_m", tour_lookahead_m, 0.0, 1e4);
  requireInRange("near_openings_radius_m", near_openings_radius_m, 0.0, 1e4);
  requireInRange("near_openings_min_cells", near_openings_min_cells, 1, 1000000);
  if (bounds_world_m) {
    requireThat(bounds_world_m->min().allFinite() && bounds_world_m->max().allFinite(),
                "bounds_world_m", "corners must be finite");
    requireThat(!bounds_world_m->isEmpty(), "bounds_world_m", "min must not exceed max");
  }
}

const char* toString(GoalRefusal r) {
  switch (r) {
    case GoalRefusal::kNotCurrent:
      return "not_current";
    case GoalRefusal::kSetAside:
      return "set_aside";
    case GoalRefusal::kCountedReached:
      return "counted_reached";
  }
  return "unknown";
}

const char* toString(ReplanReason r) {
  switch (r) {
    case ReplanReason::kFirstPlan:
      return "first_plan";
    case ReplanReason::kNewHypotheses:
      return "new_hypotheses";
    case ReplanReason::kGoalRefused:
      return "goal_refused";
    case ReplanReason::kNoProgress:
      return "no_progress";
    case ReplanReason::kNoGoal:
      return "no_goal";
    case ReplanReason::kTargetReached:
      return "target_reached";
    case ReplanReason::kHalfWay:
      return "half_way";
    case ReplanReason::kTargetGone:
      return "target_gone";
    case ReplanReason::kPeriod:
      return "period";
  }
  return "unknown";
}

const char* toString(ExplorationState s) {
  switch (s) {
    case ExplorationState::kWaitingForData:
      return "waiting_for_data";
    case ExplorationState::kExploring:
      return "exploring";
    case ExplorationState::kFinished:
      return "finished";
    case ExplorationState::kStuck:
      return "stuck";
  }
  return "unknown";
}

namespace {

const ExplorationManagerConfig& validated(const ExplorationManagerConfig& c) {
  c.validate();
  return c;
}

}  // namespace

ExplorationManager::ExplorationManager(const ExplorationManagerConfig& config,
                                       std::optional<GuidepointPrior> prior)
    : config_(validated(config)),
      prior_(std::move(prior)),
      observation_(config_.observation),
      occupancy_(config_.occupancy),
      opening_cells_(occupancy_, config_.bounds_world_m),
      known_columns_(occupancy_),
      clusters_(config_.frontier),
      viewpoint_manager_(ViewpointSampler(config_.viewpoint, config_.fov)),
      path_cache_(occupancy_, config_.path),
      planner_(config_.planner),
      opening_membership_(config_.openings_stay_in_tour),
      reached_openings_(config_.reached_openings),
      stall_(config_.last_resort_stall) {
  if (prior_) prior_->validate();
  if (config_.fine_path_resolution_factor > 1) {
    PathSearchConfig fine = config_.path;
    fine.search_resolution_m /= config_.fine_path_resolution_factor;
    fine_search_ = std::make_unique<PathSearch>(occupancy_, fine);
  }
  target_.message = "no scan yet";
}

void ExplorationManager::insertScan(const Eigen::Vector3d& origin,
                                    const std::vector<Eigen::Vector3f>& points) {
  if (points.empty()) {
    ++stats_.scans_empty;
    return;
  }
  if (!origin.allFinite()) {
    ++stats_.scans_rejected;
    pending_message_ = "scan refused: sensor origin is not finite";
    return;
  }
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(points.size());
  size_t dropped = 0;
  for (const Eigen::Vector3f& p : points) {
    if (p.allFinite())
      pts.push_back(p.cast<double>());
    else
      ++dropped;
  }
  stats_.points_dropped_nonfinite += dropped;
  if (dropped > 0) {
    std::ostringstream os;
    os << "dropped " << dropped << " non-finite point(s) of " << points.size() << " in a scan";
    pending_message_ = os.str();
  }
  if (pts.empty()) {
    ++stats_.scans_empty;
    return;
  }
  observation_.insertScan(origin, pts);
  occupancy_.insertScan(origin, pts);
  if (config_.use_openings) opening_cells_.update();  // else never asked: a plain cost per scan
  if (config_.use_openings && config_.openings.vouched_min_cells > 0) known_columns_.update();
  path_cache_.sync();
  ++stats_.scans_inserted;
  map_dirty_ = true;
}

void ExplorationManager::setHypotheses(std::vector<Hypothesis> hypotheses) {
  std::vector<Hypothesis> usable;
  std::string why_not;
  for (Hypothesis& h : hypotheses) {
    if (auto defect = hypothesisDefect(h)) {
      ++stats_.hypotheses_rejected;
      why_not +=
          (why_not.empty() ? "" : "; ") + ("hypothesis " + std::to_string(h.id) + ": " + *defect);
    } else {
      usable.push_back(h);
    }
  }
  if (!why_not.empty()) pending_message_ = "hypotheses refused: " + why_not;
  // "Still none" changes nothing: a replan at every registration frame made a flight with a
  // sketch that never registered differ from the prior-free one.
  if (hypotheses_.empty() && usable.empty()) return;
  hypotheses_ = std::move(usable);
  hypotheses_changed_ = true;
}

void ExplorationManager::refreshMapProducts() {
  if (!map_dirty_) return;
  clusters_.update(observation_);
  viewpoint_manager_.update(clusters_, occupancy_, observation_.resolution());
  map_dirty_ = false;
}

GoalRefusal ExplorationManager::reportGoalUnreachable(const Eigen::Vector3d& goal_world_m,
                                                      double time_s) {
  // The goal travels as float64 through ROS and back unchanged; the tolerance only absorbs a
  // conversion, it does not match a neighbouring goal.
  constexpr double kSameGoal_m = 1e-3;
  if (!goal_world_m.allFinite() || !std::isfinite(time_s) || !target_.has_goal ||
      !target_.goal_viewpoint_id || (goal_world_m - target_.goal_world_m).norm() > kSameGoal_m)
    return GoalRefusal::kNotCurrent;
  const int id = *target_.goal_viewpoint_id;
  const double distance_m = (target_.viewpoint_world_m - last_robot_world_m_).norm();
  const bool near = distance_m <= config_.unreachable_near_m;
  if (near) {
    markTargetReached();
    ++stats_.goals_refused_near;
  } else {
    setAside(id, time_s);
  }
  refused_goals_.push_back({goal_world_m, time_s + config_.unreachable_retry_s});
  if (progress_ && progress_->viewpoint_id == id) progress_.reset();
  goal_refused_ = true;
  ++stats_.goals_refused;
  std::ostringstream os;
  os << "the local planner found no way to the goal (" << goal_world_m.x() << ", "
     << goal_world_m.y() << ", " << goal_world_m.z() << "): viewpoint " << id
     << (near ? " counted as reached, " : " set aside, ") << std::round(10.0 * distance_m) / 10.0
     << " m away";
  pending_message_ = os.str();
  return near ? GoalRefusal::kCountedReached : GoalRefusal::kSetAside;
}

std::optional<ReplanReason> ExplorationManager::replanDue(double time_s,
                                                          const RobotPose& robot) const {
  if (!last_plan_time_s_) return ReplanReason::kFirstPlan;
  if (hypotheses_changed_) return ReplanReason::kNewHypotheses;
  if (goal_refused_) return ReplanReason::kGoalRefused;
  if (!target_.has_goal || !target_.goal_viewpoint_id) return ReplanReason::kNoGoal;
  if (target_passed_) return ReplanReason::kTargetReached;
  // Half-way to a goal that is not the viewpoint itself (a stage on the way, or a point past it
  // along the tour): the next one is due before the local planner slows down for it.
  if (target_.goal_world_m != target_.viewpoint_world_m &&
      (robot.position_world_m - target_.goal_world_m).norm() <= 0.5 * goal_distance_at_plan_m_)
    return ReplanReason::kHalfWay;
  // An opening stays the target until the next periodic plan looks again; a viewpoint is gone
  // once its frontier was observed or it became unsafe.
  const int id = *target_.goal_viewpoint_id;
  const auto alive = [&] {
    if (opening_look_at_.count(id)) return true;
    for (const auto& [cluster, vps] : viewpoint_manager_.byCluster())
      for (const Viewpoint& v : vps)
        if (v.id == id) return true;
    return false;
  };
  if (!alive()) return ReplanReason::kTargetGone;
  if (time_s - *last_plan_time_s_ >= config_.replan_period_s) return ReplanReason::kPeriod;
  return std::nullopt;
}

void ExplorationManager::replan(double time_s, const RobotPose& robot) {
  // A target the robot reached (or passed since the last update) is not planned for again.
  if (target_.has_goal && target_.goal_viewpoint_id && target_passed_) markTargetReached();
  target_passed_ = false;

  for (auto it = set_aside_until_s_.begin(); it != set_aside_until_s_.end();)
    it = it->second <= time_s ? set_aside_until_s_.erase(it) : std::next(it);
  refused_goals_.erase(std::remove_if(refused_goals_.begin(), refused_goals_.end(),
                                      [&](const RefusedGoal& r) { return r.until_s <= time_s; }),
                       refused_goals_.end());
  std::map<int, Eigen::Vector3d> centroid;
  for (const auto& [id, c] : clusters_.clusters()) centroid[id] = c.centroid_world_m;
  std::vector<PlanViewpoint> vps;
  std::vector<int> vp_cluster;
  std::set<int> alive;
  int set_aside = 0;
  int given_up = 0;
  int looked_at = 0;
  int reached_alive = 0;
  for (auto it = looked_at_cells_.begin(); it != looked_at_cells_.end();)
    it = observation_.isFrontier(*it) ? std::next(it) : looked_at_cells_.erase(it);
  std::map<int, bool> cluster_looked_at;
  // Alive, not reached, not set aside, not given up: a candidate.
  const auto candidate = [&](int id, bool reached) {
    alive.insert(id);
    if (reached) {
      ++reached_alive;
      return false;
    }
    if (givenUp(id)) {
      ++given_up;
      return false;
    }
    if (!set_aside_until_s_.count(id)) return true;
    ++set_aside;
    return false;
  };
  // Searched at most once per plan, whatever the retry below does (but for the pockets the
  // sketch vouches for, searched for at the end).
  std::optional<std::vector<Opening>> openings;
  std::vector<Eigen::Vector2d> vouched;
  bool revisit_moved_openings = false;
  int moved_openings = 0;
  const auto collect = [&] {
    vps.clear();
    vp_cluster.clear();
    alive.clear();
    set_aside = given_up = looked_at = moved_openings = reached_alive = 0;
    for (const Viewpoint& v : viewpoint_manager_.all()) {
      if (!candidate(v.id, reached_viewpoint_ids_.count(v.id) > 0)) continue;
      const auto memo = cluster_looked_at.try_emplace(v.cluster_id, false);
      if (memo.second) memo.first->second = lookedAt(v.cluster_id);
      if (memo.first->second) {
        ++looked_at;
        continue;
      }
      vps.push_back({v.id, v.position_world_m, v.yaw_rad});
      vp_cluster.push_back(v.cluster_id);
    }
    // No surface viewpoint left, or none near: the ways on that the surface frontiers cannot
    // see (openings.h), all of them or the near ones.
    opening_look_at_.clear();
    if (config_.use_openings) {
      std::vector<Eigen::Vector3d> surface;
      for (const PlanViewpoint& v : vps) surface.push_back(v.position_world_m);
      const auto find = [&]() -> const std::vector<Opening>& {
        if (!openings)
          openings = findOpenings(occupancy_, opening_cells_.cells(), robot.position_world_m,
                                  config_.openings, vouched);
        return *openings;
      };
      for (const Opening& o : opening_membership_.select(surface, robot.position_world_m,
                                                         config_.near_openings_radius_m,
                                                         config_.near_openings_min_cells, find)) {
        const bool moved_on = reached_openings_.movedOn(o);
        moved_openings += moved_on;
        if (!candidate(o.id, reached_openings_.visited(o) && !(revisit_moved_openings && moved_on)))
          continue;
        vps.push_back({o.id, o.viewpoint_world_m, o.yaw_rad});
        vp_cluster.push_back(-1);
        opening_look_at_[o.id] =
            o.viewpoint_world_m +
            3.0 * Eigen::Vector3d(std::cos(o.yaw_rad), std::sin(o.yaw_rad), 0.0);
      }
    }
  };
  collect();
  // Nothing else to do: waiting out the retry time would only hover in place, so what was set
  // aside gets its next attempt now (and is given up once it has had unreachable_attempts).
  std::string retry_note;
  if (vps.empty() && set_aside > 0) {
    retry_note = ", " + std::to_string(set_aside) + " set aside retried early (nothing else left)";
    set_aside_until_s_.clear();
    refused_goals_.clear();
    collect();
  }
  // Still nothing: the reached openings that have moved on since get another look before the
  // exploration ends (ReachedOpenings). Only then: revisiting them as soon as they moved slowed
  // the small garage's guided flight (seed 1) from 79.1 to 85.4 s.
  bool last_resorts = false;
  if (vps.empty() && moved_openings > 0) {
    last_resorts = true;
    retry_note += ", " + std::to_string(moved_openings) +
                  " reached opening(s) that moved on looked at again (nothing else left)";
    revisit_moved_openings = true;
    collect();
  }
  // Still nothing: the pockets the sketch vouches for (OpeningConfig::vouched_min_cells), a door
  // seen edge-on with the room the drawing shows behind it. Only now: toured beside the rest,
  // those beside places no flight can enter (a garage's closed service core) drew the small
  // garage's flights across it (precise seed 3 68.2 -> 87.4 s).
  if (vps.empty() && config_.use_openings && config_.openings.vouched_min_cells > 0) {
    vouched =
        unseenPlaces(known_columns_, vouchingPlaces(), config_.openings.vouched_unseen_radius_m,
                     config_.openings.vouched_unseen_fraction);
    if (!vouched.empty()) {
      openings.reset();
      collect();
      if (!vps.empty()) {
        last_resorts = true;
        retry_note += ", " + std::to_string(vps.size()) +
                      " opening(s) the sketch vouches for looked at (nothing else left)";
      }
    }
  }
  // The last resorts are looked at while looking pays (last_resort_stall).
  const size_t well_observed = observation_.numWellObserved();
  stall_.record(time_s, well_observed);
  stall_note_.clear();
  if (last_resorts && !vps.empty() && stall_.stalled(time_s)) {
    std::ostringstream os;
    os << " (" << vps.size()
       << " last resort(s) given up: " << stall_.cellsSinceLastGain(well_observed)
       << " well-observed cells gained in the last "
       << std::round(time_s - *stall_.lastGainTime_s()) << " s, " << stall_.cellsToGain()
       << " wanted)";
    stall_note_ = os.str();
    vps.clear();
    vp_cluster.clear();
    opening_look_at_.clear();
  }
  for (const PlanViewpoint& old : viewpoints_)
    if (!alive.count(old.id)) path_cache_.forget(static_cast<uint64_t>(old.id));
  for (auto it = reached_viewpoint_ids_.begin(); it != reached_viewpoint_ids_.end();)
    it = alive.count(*it) ? std::next(it) : reached_viewpoint_ids_.erase(it);
  viewpoints_ = std::move(vps);
  viewpoint_cluster_ = std::move(vp_cluster);

  PlanningInput in;
  in.robot = robot;
  in.viewpoints = viewpoints_;
  // L(X_r, V) for every viewpoint with one search from the robot (the robot moved since the
  // last plan, so none of these would be cached); viewpoint pairs come from the cache.
  std::vector<Eigen::Vector3d> targets;
  for (const PlanViewpoint& v : viewpoints_) targets.push_back(v.position_world_m);
  robot_len_.clear();
  for (const std::optional<double>& l :
       path_cache_.search().lengthsFrom(robot.position_world_m, targets))
    robot_len_.push_back(l ? *l : kUnreachable);
  // None reachable: the robot may stand where the lattice's spacing finds no way out (a narrow
  // mouth), so its paths are searched again on the fine lattice.
  robot_on_fine_lattice_ = false;
  if (fine_search_ && !targets.empty() &&
      std::all_of(robot_len_.begin(), robot_len_.end(),
                  [](double l) { return l == kUnreachable; })) {
    const auto fine = fine_search_->lengthsFrom(robot.position_world_m, targets);
    for (size_t i = 0; i < fine.size(); ++i) {
      if (!fine[i]) continue;
      robot_len_[i] = *fine[i];
      robot_on_fine_lattice_ = true;
    }
  }
  in.path_length_m = makePathLengthFn(path_cache_, robot_len_, viewpoints_);
  in.hypotheses = hypotheses_;
  in.prior = prior_ ? &*prior_ : nullptr;
  in.observation = makeObservationQuery(observation_);
  if (config_.bounds_world_m)
    in.bounds_world_m = Eigen::AlignedBox2d(config_.bounds_world_m->min().head<2>(),
                                            config_.bounds_world_m->max().head<2>());
  plan_hypotheses_ = hypotheses_;
  last_plan_ = planner_.plan(in);
  // A plan without viewpoints has no guiding hypothesis; the one before it still says where the
  // sketch vouches for unseen places, while hypotheses remain.
  if (const std::optional<size_t> k = activeUsedIndex())
    guiding_T_world_sketch_ = plan_hypotheses_[last_plan_->used_hypotheses[*k]].T_world_sketch;
  else if (hypotheses_.empty())
    guiding_T_world_sketch_.reset();
  last_plan_time_s_ = time_s;
  hypotheses_changed_ = false;
  goal_refused_ = false;

  const PlanningResult& plan = *last_plan_;
  if (plan.status != PlanningStatus::kNoViewpoints) nothing_left_.reset();
  target_.replanned = true;
  target_.mode_used = plan.mode_used;
  target_.active_hypothesis_id =
      plan.active_hypothesis_id >= 0 ? std::optional<int>(plan.active_hypothesis_id) : std::nullopt;
  target_.tour_world_m.clear();
  target_.has_goal = false;
  target_.goal_viewpoint_id.reset();
  switch (plan.status) {
    case PlanningStatus::kNoViewpoints: {
      if (!nothing_left_) nothing_left_ = NothingLeft{time_s, stats_.scans_inserted};
      const double held_s = time_s - nothing_left_->since_s;
      if (config_.finish_confirmation_s > 0.0 &&
          (held_s < config_.finish_confirmation_s ||
           stats_.scans_inserted == nothing_left_->scans_inserted)) {
        target_.state = ExplorationState::kExploring;
        std::ostringstream os;
        os << "no viewpoint remains for " << std::round(10.0 * held_s) / 10.0
           << " s: the end is confirmed after " << config_.finish_confirmation_s
           << " s with new scans" << stall_note_;
        plan_message_ = os.str();
        return;
      }
      target_.state = ExplorationState::kFinished;
      plan_message_ = "no viewpoint remains: exploration finished" + stall_note_;
      if (reached_alive > 0)
        plan_message_ += " (" + std::to_string(reached_alive) +
                         " reached and still there: its frontier or opening not cleared from it)";
      if (looked_at > 0)
        plan_message_ += " (" + std::to_string(looked_at) +
                         " left whose frontier was looked at from a reached viewpoint)";
      if (given_up > 0)
        plan_message_ += " (" + std::to_string(given_up) +
                         " left unvisited, given up as unreachable after " +
                         std::to_string(config_.unreachable_attempts) + " attempt(s) each)";
      return;
    }
    case PlanningStatus::kNoReachableViewpoint:
      // Each is one attempt: the next update plans again, and those the search never reaches
      // are given up in the end.
      for (const PlanViewpoint& v : viewpoints_) setAside(v.id, time_s);
      target_.state = ExplorationState::kStuck;
      goal_refused_ = true;
      plan_message_ = std::to_string(viewpoints_.size()) +
                      " viewpoint(s) remain but none is reachable from the robot: set aside";
      return;
    case PlanningStatus::kOk:
      break;
  }
  if (plan.tour.viewpoints.empty()) {
    target_.state = ExplorationState::kStuck;
    plan_message_ = "the planner returned an empty tour";
    return;
  }
  // A goal point the local planner gave up on is not sent again while it is refused: the
  // look-ahead along the next viewpoint's path can land on the very same point. Then the
  // viewpoint itself is the goal (when within reach); failing that, the viewpoint is set aside
  // and the next one of the tour is tried.
  std::vector<int> tour = plan.tour.viewpoints;
  std::optional<Eigen::Vector3d> goal_m;
  while (!tour.empty() && !goal_m) {
    const PlanViewpoint& v = viewpoints_[tour.front()];
    const bool near = withinGoalReach(robot.position_world_m, v.position_world_m);
    const Eigen::Vector3d g = near ? tourGoal(robot.position_world_m, tour)
                                   : stagedGoal(robot.position_world_m, v.position_world_m);
    if (!refusedGoal(g)) {
      goal_m = g;
    } else if (near && !refusedGoal(v.position_world_m)) {
      goal_m = v.position_world_m;
    } else {
      setAside(v.id, time_s);
      ++set_aside;
      tour.erase(tour.begin());
    }
  }
  if (!goal_m) {
    // Every viewpoint of this tour is set aside now; the next update plans over the others
    // (and says kStuck only if none is left).
    target_.state = ExplorationState::kExploring;
    goal_refused_ = true;
    plan_message_ = "every viewpoint of the tour led to a goal the local planner gave up on: " +
                    std::to_string(set_aside) + " set aside, replanning";
    return;
  }
  for (int i : tour) target_.tour_world_m.push_back(viewpoints_[i].position_world_m);
  const int first = tour.front();
  const PlanViewpoint& goal = viewpoints_[first];
  target_.state = ExplorationState::kExploring;
  target_.has_goal = true;
  target_.viewpoint_world_m = goal.position_world_m;
  target_.goal_world_m = *goal_m;
  goal_distance_at_plan_m_ = (target_.goal_world_m - robot.position_world_m).norm();
  target_.goal_yaw_rad = goal.yaw_rad;
  target_.goal_viewpoint_id = goal.id;
  const auto c = centroid.find(viewpoint_cluster_[first]);
  const auto o = opening_look_at_.find(goal.id);
  target_.look_at_world_m = c != centroid.end()           ? c->second
                            : o != opening_look_at_.end() ? o->second
                                                          : goal.position_world_m;
  // In transit the sensor looks where the vehicle goes: the Mid-360 sees little below the
  // horizon behind it, and the local planner's map of a passage flown before is forgotten (seen:
  // a cave floor hit flying back down a sloping passage with the sensor facing the far target).
  if (target_.goal_world_m != target_.viewpoint_world_m)
    target_.look_at_world_m = target_.goal_world_m;
  std::ostringstream os;
  os << "exploring (" << toString(plan.mode_used) << "), " << viewpoints_.size()
     << (opening_look_at_.empty() ? " viewpoint(s)" : " opening(s)") << ", tour of "
     << plan.tour.viewpoints.size();
  if (target_.goal_world_m != target_.viewpoint_world_m) os << ", staged goal on the way";
  if (!plan.tour.unreachable_viewpoints.empty())
    os << ", " << plan.tour.unreachable_viewpoints.size() << " unreachable";
  if (set_aside > 0) os << ", " << set_aside << " set aside (unreachable)";
  if (given_up > 0) os << ", " << given_up << " given up";
  if (looked_at > 0)
    os << ", " << looked_at << " left whose frontier was looked at from a reached viewpoint";
  os << retry_note;
  plan_message_ = os.str();
  const double length = robot_len_[first];
  if (!progress_ || progress_->viewpoint_id != goal.id) {
    progress_ = Progress{goal.id, length, time_s};
  } else if (length < progress_->best_length_m - config_.target_progress_m) {
    progress_->best_length_m = length;
    progress_->since_s = time_s;
  }
}

bool ExplorationManager::checkProgress(double time_s) {
  if (!target_.has_goal || !target_.goal_viewpoint_id || !progress_ ||
      progress_->viewpoint_id != *target_.goal_viewpoint_id)
    return true;
  if (time_s - progress_->since_s < config_.target_progress_timeout_s) return true;
  setAside(progress_->viewpoint_id, time_s);
  progress_.reset();
  return false;
}

void ExplorationManager::markTargetReached() {
  const int id = *target_.goal_viewpoint_id;
  if (opening_look_at_.count(id)) {
    reached_openings_.markReached(id, target_.viewpoint_world_m);
    return;
  }
  reached_viewpoint_ids_.insert(id);
  if (!config_.skip_looked_at_clusters) return;
  for (const auto& [cluster_id, vps] : viewpoint_manager_.byCluster()) {
    for (const Viewpoint& v : vps) {
      if (v.id != id) continue;
      const auto c = clusters_.clusters().find(cluster_id);
      if (c != clusters_.clusters().end())
        looked_at_cells_.insert(c->second.cells.begin(), c->second.cells.end());
      return;
    }
  }
}

bool ExplorationManager::lookedAt(int cluster_id) const {
  if (!config_.skip_looked_at_clusters || looked_at_cells_.empty()) return false;
  const auto c = clusters_.clusters().find(cluster_id);
  if (c == clusters_.clusters().end() || c->second.cells.empty()) return false;
  size_t n = 0;
  for (const VoxelKey& k : c->second.cells) n += looked_at_cells_.count(k);
  return static_cast<double>(n) >= config_.looked_at_fraction * c->second.cells.size();
}

void ExplorationManager::setAside(int id, double time_s) {
  set_aside_until_s_[id] = time_s + config_.unreachable_retry_s;
  if (++set_aside_count_[id] == config_.unreachable_attempts) ++stats_.viewpoints_given_up;
}

bool ExplorationManager::givenUp(int id) const {
  const auto it = set_aside_count_.find(id);
  return it != set_aside_count_.end() && it->second >= config_.unreachable_attempts;
}

bool ExplorationManager::refusedGoal(const Eigen::Vector3d& goal_world_m) const {
  for (const RefusedGoal& r : refused_goals_)
    if ((r.goal_world_m - goal_world_m).norm() <= kRefusedGoalRadius_m) return true;
  return false;
}

bool ExplorationManager::withinGoalReach(const Eigen::Vector3d& from,
                                         const Eigen::Vector3d& to) const {
  return (to - from).head<2>().norm() <= config_.max_goal_distance_m &&
         std::abs(to.z() - from.z()) <= config_.max_goal_climb_m;
}

Eigen::Vector3d ExplorationManager::stagedGoal(const Eigen::Vector3d& from,
                                               const Eigen::Vector3d& viewpoint) {
  if (withinGoalReach(from, viewpoint)) return viewpoint;
  const PathSearchResult r = searchFromRobot(from, viewpoint);
  if (!r.length_m || r.waypoints_world_m.size() < 2) return viewpoint;
  const double inf = std::numeric_limits<double>::infinity();
  return goalAlongPath(r.waypoints_world_m, inf, inf,
                       [&](const Eigen::Vector3d& p) { return withinGoalReach(from, p); });
}

Eigen::Vector3d ExplorationManager::tourGoal(const Eigen::Vector3d& from,
                                             const std::vector<int>& tour) {
  const PlanViewpoint& first = viewpoints_[tour.front()];
  if (config_.tour_lookahead_m <= 0.0) return first.position_world_m;
  const PathSearchResult r = searchFromRobot(from, first.position_world_m);
  if (!r.length_m || r.waypoints_world_m.size() < 2) return first.position_world_m;
  std::vector<Eigen::Vector3d> path = r.waypoints_world_m;
  double length = *r.length_m;
  const double to_first_m = length;
  // Further legs only while the look-ahead reaches past the end of the path so far.
  for (size_t k = 1; k < tour.size() && length < config_.tour_lookahead_m; ++k) {
    const PlanViewpoint& a = viewpoints_[tour[k - 1]];
    const PlanViewpoint& b = viewpoints_[tour[k]];
    if (!withinGoalReach(from, a.position_world_m)) break;
    const std::vector<Eigen::Vector3d> leg =
        path_cache_.path(static_cast<uint64_t>(a.id), a.position_world_m,
                         static_cast<uint64_t>(b.id), b.position_world_m);
    if (leg.size() < 2) break;
    path.insert(path.end(), leg.begin() + 1, leg.end());
    for (size_t i = 1; i < leg.size(); ++i) length += (leg[i] - leg[i - 1]).norm();
  }
  // Past the first viewpoint only while the path leads on away from the robot: a tour that
  // turns back (to a viewpoint behind) put the goal beside the robot, which then hovered there
  // and never reached the first viewpoint (seen in the garage).
  return goalAlongPath(path, config_.tour_lookahead_m, to_first_m,
                       [&](const Eigen::Vector3d& p) { return withinGoalReach(from, p); });
}

PathSearchResult ExplorationManager::searchFromRobot(const Eigen::Vector3d& from,
                                                     const Eigen::Vector3d& to) {
  PathSearchResult r = path_cache_.search().search(from, to);
  if (!r.length_m && robot_on_fine_lattice_) r = fine_search_->search(from, to);
  return r;
}

void ExplorationManager::appendThroughGuide(const std::vector<Eigen::Vector2d>& sketch_m,
                                            std::vector<Eigen::Vector2d>& world_m) const {
  if (guiding_T_world_sketch_)
    for (const Eigen::Vector2d& p : sketch_m) world_m.push_back(guiding_T_world_sketch_->apply(p));
}

std::vector<Eigen::Vector2d> ExplorationManager::guidingGuidepoints() const {
  std::vector<Eigen::Vector2d> out;
  if (prior_) appendThroughGuide(prior_->positions_sketch_m, out);
  return out;
}

std::vector<Eigen::Vector2d> ExplorationManager::vouchingPlaces() const {
  std::vector<Eigen::Vector2d> out = guidingGuidepoints();
  if (prior_) appendThroughGuide(prior_->predicted_free_sketch_m, out);
  return out;
}

std::optional<size_t> ExplorationManager::activeUsedIndex() const {
  if (!last_plan_ || last_plan_->active_hypothesis_id < 0) return std::nullopt;
  const PlanningResult& p = *last_plan_;
  for (size_t k = 0; k < p.used_hypotheses.size() && k < p.attachments.size(); ++k)
    if (plan_hypotheses_[p.used_hypotheses[k]].id == p.active_hypothesis_id) return k;
  return std::nullopt;
}

const HypothesisAttachment* ExplorationManager::activeAttachment() const {
  const std::optional<size_t> k = activeUsedIndex();
  return k ? &last_plan_->attachments[*k] : nullptr;
}

std::vector<Eigen::Vector2d> ExplorationManager::activeGuidepointSequence() const {
  std::vector<Eigen::Vector2d> out;
  const HypothesisAttachment* a = activeAttachment();
  if (!a) return out;
  for (int g : last_plan_->selection.guidepoint_sequence) out.push_back(a->guidepoints_world_m[g]);
  return out;
}

const ExplorationTarget& ExplorationManager::update(double time_s, const RobotPose& robot) {
  target_.replanned = false;
  if (!std::isfinite(time_s) || !robot.position_world_m.allFinite() ||
      !std::isfinite(robot.yaw_rad)) {
    ++stats_.updates_rejected;
    target_.message = "update refused: time or robot pose is not finite";
    return target_;
  }
  if (last_time_s_ && time_s < *last_time_s_) {
    ++stats_.updates_rejected;
    std::ostringstream os;
    os << "update refused: time went backwards (" << time_s << " s after " << *last_time_s_
       << " s)";
    target_.message = os.str();
    return target_;
  }
  // Updates sample the robot's path: at 2 Hz (the node's plan_rate_hz until 1ad3910, or what a
  // loaded computer falls to) it moves 1.5-2 m between two, and it flies through the viewpoints
  // of a tour (tour_lookahead_m), so a viewpoint passed within target_reached_m between updates
  // counts as reached. Before, one not within it at an update stayed the target and the robot
  // turned back for it (small garage, precise sketch, planner at 2 Hz: 118.6 s and 336 m to
  // explore, 80.1 s and 226 m updating after every scan).
  // The path between two updates is taken as straight; a longer step than the vehicle flies
  // between any two updates is an odometry jump, and only where it ended counts.
  constexpr double kLongestStep_m = 10.0;
  if (target_.has_goal && target_.goal_viewpoint_id) {
    const bool path_known =
        last_time_s_ && (robot.position_world_m - last_robot_world_m_).norm() <= kLongestStep_m;
    const Eigen::Vector3d& from = path_known ? last_robot_world_m_ : robot.position_world_m;
    target_passed_ =
        target_passed_ || distanceToSegment<3>(target_.viewpoint_world_m, from,
                                               robot.position_world_m) <= config_.target_reached_m;
  }
  last_time_s_ = time_s;
  last_robot_world_m_ = robot.position_world_m;
  if (stats_.scans_inserted == 0) {
    target_.state = ExplorationState::kWaitingForData;
    target_.has_goal = false;
    target_.message = pending_message_.empty() ? "no scan yet" : pending_message_;
    pending_message_.clear();
    return target_;
  }
  refreshMapProducts();
  std::optional<ReplanReason> reason =
      checkProgress(time_s) ? replanDue(time_s, robot) : ReplanReason::kNoProgress;
  if (reason) {
    target_.replan_reason = *reason;
    replan(time_s, robot);
  }
  target_.message = plan_message_;
  if (!pending_message_.empty()) {
    target_.message += "; " + pending_message_;
    pending_message_.clear();
  }
  return target_;
}

}  // namespace efs::planner
