// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Openings: the free-space frontiers of the occupancy map (known free cells with an unknown
// horizontal neighbour, inside the exploration box), clustered, with one viewpoint each. The
// surface frontiers of the observation map (EPIC's, paper Sec. VI-A) miss a door to an unseen
// room: what the LiDAR saw through it is close, hence well observed, and its edge borders
// unknown space, not a poorly observed surface (seen: a real office, ed21, "explored" after one
// second from a 3 x 4 m room). The exploration manager tours them beside the surface
// viewpoints, from a flight's first plan on (OpeningTourMembership below), and keeps their cells
// scan by scan (opening_cells.h).
// Unknown cells above and below do not count: the Mid-360 sees little up and down, and a
// ceiling or floor not seen yet is a surface for the observation map, not a way into new space.
// Cells right above a floor (two cells) or below a ceiling do not count either (the space under
// a desk; seen: a collision 0.35 m above an office floor flying to such an opening).
// The viewpoint is where the vehicle may hover and look through the opening: a known-free ball
// of viewpoint_clearance_m, stepped back from the opening into the known space when the opening
// itself borders the unknown, or found along the known free space (back along the rays) when the
// space around the opening was seen only from afar. An opening cell can sit right above a floor the
// LiDAR never saw (seen: a goal 0.15 m above a cave floor, unknown to both maps, and a collision
// there).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "prior_guided_planner/known_columns.h"
#include "prior_guided_planner/occupancy_map.h"
#include "prior_guided_planner/opening_cells.h"

namespace efs::planner {

struct OpeningConfig {
  /// Clusters of fewer opening cells are pockets (a hollow in a cave wall, a corner the rays
  /// missed), not a way on: a door seen from its room leaves several times this many, and a
  /// pocket toured once nothing else is left can cost a trip across the whole map. Measured
  /// sizes and the flight that set the value: README, "Doorways the surface frontiers cannot
  /// see"; the door scene: openings_test.
  int min_cells = 20;
  /// The viewpoint needs a known-free ball of this radius (no occupied and no unknown cell), as
  /// a surface viewpoint does (ViewpointConfig::clearance_m).
  double viewpoint_clearance_m = 0.5;
  /// When no opening has a place for that ball, the search is made again with this smaller one
  /// (the local planner's narrow clearance): seen from a small room, the space behind its door
  /// is known free only along the rays through it. 0: off.
  double narrow_viewpoint_clearance_m = 0.36;
  /// How far the viewpoint is looked for back from the opening, away from the unknown side [m],
  /// before it is looked for along the known free space (max_walk_cells).
  double max_backoff_m = 2.0;
  /// Failing that, the viewpoint is the first place with the ball found walking breadth first
  /// over known-free cells from the opening, at most this many cells (0: no walk). It used to be
  /// looked for on the straight way back to the robot, which made the place follow the robot: in
  /// ed21 the rooms of the south-west wing, seen through a door from the corridor 5-10 m away,
  /// had their viewpoints where the vehicle stood, were "reached" there without a step towards
  /// them, and were left as dead ends (ReachedOpenings): three of four guided flights ended at
  /// 82 % coverage. The walk follows the rays back through the door to where the space around
  /// them is known free, a place that moves only as the map does. The straight way back remains
  /// the last resort.
  int max_walk_cells = 20000;
  /// A cluster of fewer than min_cells is still a way on when it has at least vouched_min_cells
  /// and a place the sketch vouches for (findOpenings' `vouched_xy_world_m`) lies within
  /// vouched_radius_m of its centre, horizontally, in view across unknown space. A door seen
  /// edge-on from the corridor leaves a pocket's worth of cells: in ed21 the room east of the
  /// south-east block (its door 9-14 cells as the vehicle passed, its guidepoint 3.5 m behind it
  /// in space no scan had reached) was entered by no flight, the drawings' or prior_free's. At 10
  /// cells the door fell below the bound as the vehicle came nearer. 0: off.
  int vouched_min_cells = 5;
  double vouched_radius_m = 4.0;
  /// The places that vouch are the guiding hypothesis' guidepoints and the free space the sketch
  /// predicts (its free samples, 1 sketch m apart): a drawing may put a room's only guidepoint
  /// in its door, with the corridor's seen space around it (ed21, `sketch_ed21_2`: 0.6 m inside
  /// the door of the room east of the south-east block, seen from the corridor only at a
  /// grazing angle; the drawing's flight never entered it and ended at 94.8 %).
  /// A place vouches only with room around it: at least vouched_unseen_fraction of the
  /// columns within vouched_unseen_radius_m of it unseen at every height (unseenPlaces). A
  /// hypothesis that puts a guidepoint a little off, into a wall or just past the end of a
  /// corridor, leaves known walls and free space beside it: in the small indoor world (partial
  /// sketch, seed 4) such a guidepoint had 0.72 of 2 m unseen, and its opening was looked at three
  /// times for nothing at the end of the flight (12 s); the two guidepoints in the room behind
  /// ed21's door had 0.90 and 0.96 (cells at the flight height, measured before whole columns
  /// counted). Radius 0: the place's own column decides.
  double vouched_unseen_radius_m = 2.0;
  double vouched_unseen_fraction = 0.8;
  /// Openings beyond this horizontal range of the robot are left out [m]. Openings are asked for
  /// once no surface viewpoint is left, and then every one belongs in the tour: at 60 m the
  /// far ones of a 150 x 110 m building entered and left the set as the vehicle moved, and it
  /// crossed the building three times for the last three (paper indoor, 152 s on 7-8 openings).
  /// The opening cells are kept for the whole map whatever the range; the range bounds the
  /// clusters given a viewpoint.
  double search_radius_m = 1000.0;
  void validate() const;
};

struct Opening {
  /// Stable while the opening exists: built from its smallest cell key.
  int id = 0;
  Eigen::Vector3d viewpoint_world_m = Eigen::Vector3d::Zero();
  double yaw_rad = 0.0;  ///< toward the unknown side
  int cells = 0;
};

/// The openings within search_radius_m of `robot_world_m` (and inside `bounds_world_m` when
/// given), largest first. Finds the opening cells by a pass over the whole map.
std::vector<Opening> findOpenings(const OccupancyMap& occupancy,
                                  const Eigen::Vector3d& robot_world_m,
                                  const std::optional<Eigen::AlignedBox3d>& bounds_world_m,
                                  const OpeningConfig& config = {});
/// The same from the map's opening cells (openingCellsOf, or an OpeningCellIndex's, with the
/// bounds they were found with). `vouched_xy_world_m`: places the sketch says are there to see
/// and no scan has reached (unseenPlaces); smaller clusters near them count too
/// (OpeningConfig::vouched_min_cells).
std::vector<Opening> findOpenings(const OccupancyMap& occupancy, const OpeningCells& cells,
                                  const Eigen::Vector3d& robot_world_m,
                                  const OpeningConfig& config = {},
                                  const std::vector<Eigen::Vector2d>& vouched_xy_world_m = {});

/// The places of a sketch (its guidepoints and predicted free samples, mapped into the world by a
/// hypothesis: ExplorationManager::vouchingPlaces) that lie in space no scan has reached (a room
/// the drawing shows and the flight has not looked into): no cell of its column, at any height,
/// is known to the map of `known`, and the same holds for at least `min_unseen_fraction` of the
/// columns whose centres lie within `unseen_radius_m` of it.
std::vector<Eigen::Vector2d> unseenPlaces(KnownColumns& known,
                                          const std::vector<Eigen::Vector2d>& places_world_m,
                                          double unseen_radius_m = 0.0,
                                          double min_unseen_fraction = 1.0);

/// The openings a plan tours (ExplorationManagerConfig::near_openings_radius_m): all of them
/// when no surface viewpoint is left; when no surface viewpoint lies within `near_radius_m`
/// (horizontally) of the robot, those of at least `near_min_cells` whose viewpoint is that
/// close; none otherwise. `find` (findOpenings) is called only when
/// openings are wanted. A radius of 0 wants openings only once no surface viewpoint is left.
std::vector<Opening> openingsToTour(const std::vector<Eigen::Vector3d>& surface_viewpoints_world_m,
                                    const Eigen::Vector3d& robot_world_m, double near_radius_m,
                                    int near_min_cells,
                                    const std::function<const std::vector<Opening>&()>& find);

/// Whether openings are in the tours, plan after plan (ExplorationManagerConfig::
/// openings_stay_in_tour). They join a tour when no surface viewpoint is left; with
/// `stay_once_joined` every later tour keeps all of them beside the surface viewpoints that
/// appear again, until a plan finds none. Without it, membership is openingsToTour's, plan by
/// plan, and far looks that add a few poorly observed cells pull the openings out again.
/// A flight's first plan has no surface viewpoint yet, so with `stay_once_joined` the openings
/// are in the tours from the start: ways on into unseen space, toured beside the surfaces.
class OpeningTourMembership {
 public:
  explicit OpeningTourMembership(bool stay_once_joined) : stay_once_joined_(stay_once_joined) {}

  /// The openings this plan tours (the arguments are openingsToTour's).
  std::vector<Opening> select(const std::vector<Eigen::Vector3d>& surface_viewpoints_world_m,
                              const Eigen::Vector3d& robot_world_m, double near_radius_m,
                              int near_min_cells,
                              const std::function<const std::vector<Opening>&()>& find);
  /// They joined a tour and stay in the next ones.
  bool joined() const { return joined_; }

 private:
  bool stay_once_joined_;
  bool joined_ = false;
};

/// When a reached opening is worth another look (ReachedOpenings); keys as in the planner YAML.
struct ReachedOpeningsConfig {
  /// It has moved on once its viewpoint lies this far from where it was reached [m] ...
  double moved_m = 2.0;
  /// ... and is reached at most this many times in all.
  int max_visits = 3;
  void validate() const;
};

/// The openings the vehicle reached. One that stays where it was reached is a dead end (a
/// pocket the LiDAR cannot see into from anywhere near). But an opening keeps its id (its
/// smallest cell) as it grows, and one whose viewpoint lies more than `moved_m` from where it
/// was reached leads on into space that look opened up (a door looked through in passing, the
/// room behind it now known free far in): it has moved on, and may be toured again, up to
/// `max_visits` reaches in all.
class ReachedOpenings {
 public:
  /// ConfigError (a std::invalid_argument) naming the key of a bad value.
  explicit ReachedOpenings(ReachedOpeningsConfig config = {});

  void markReached(int id, const Eigen::Vector3d& viewpoint_world_m);
  /// Whether `opening` was reached before.
  bool visited(const Opening& opening) const;
  /// Whether `opening` was reached before, has moved on since, and has visits left.
  bool movedOn(const Opening& opening) const;

 private:
  struct Visit {
    Eigen::Vector3d viewpoint_world_m;
    int count = 0;
  };
  ReachedOpeningsConfig config_;
  std::map<int, Visit> visits_;
};

}  // namespace efs::planner
