// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/openings.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "efs_common/config_check.h"
#include "observation_map_test_scenes.h"

namespace efs::planner {
namespace {

using testing::Box;
using testing::Scene;

// A 20 x 8 x 3 m hall split at x = 5 by a wall with a 1.2 m door (y in [-0.6, 0.6]), scanned
// from the left part with a 8 m range (by default): the right part is seen only through the door.
OccupancyMap scanned(bool door_open, double range_m = 8.0) {
  Scene scene;
  scene.room = {{-5, -4, 0}, {15, 4, 3}};
  if (door_open) {
    scene.solids.push_back({{5.0, -4, 0}, {5.3, -0.6, 3}});
    scene.solids.push_back({{5.0, 0.6, 0}, {5.3, 4, 3}});
  } else {
    scene.solids.push_back({{5.0, -4, 0}, {5.3, 4, 3}});
  }
  OccupancyMap occ;
  for (const Eigen::Vector3d& o :
       {Eigen::Vector3d(0, 0, 1.5), Eigen::Vector3d(2, -2, 1.2), Eigen::Vector3d(2, 2, 1.8)})
    occ.insertScan(o, scene.scanSphere(o, 1.0, range_m));
  return occ;
}

TEST(Openings, ADoorToUnseenSpaceIsAWayOn) {
  const OccupancyMap occ = scanned(true);
  const std::vector<Opening> openings = findOpenings(occ, {0, 0, 1.5}, std::nullopt);
  ASSERT_FALSE(openings.empty());
  const Opening& o = openings.front();
  // At the door (through it, or in front of it when the door is too narrow for a known-free
  // ball), looking on into the unseen part.
  const OpeningConfig defaults;
  EXPECT_GT(o.viewpoint_world_m.x(), 5.0 - defaults.max_backoff_m)
      << o.viewpoint_world_m.transpose();
  EXPECT_LT(std::abs(o.viewpoint_world_m.y()), 0.6) << o.viewpoint_world_m.transpose();
  EXPECT_GT(std::cos(o.yaw_rad), 0.5) << o.yaw_rad;
  EXPECT_TRUE(occ.isKnownFree(o.viewpoint_world_m, defaults.viewpoint_clearance_m));
  // Off the floor.
  EXPECT_GT(o.viewpoint_world_m.z(), 0.6);
  for (const Opening& p : openings)
    EXPECT_GT(p.viewpoint_world_m.x(), 5.0 - defaults.max_backoff_m);
  // Stable ids: the same map gives the same openings.
  const std::vector<Opening> again = findOpenings(occ, {0, 0, 1.5}, std::nullopt);
  ASSERT_EQ(again.size(), openings.size());
  for (size_t i = 0; i < again.size(); ++i) EXPECT_EQ(again[i].id, openings[i].id);
}

Opening openingAt(int id, const Eigen::Vector3d& viewpoint_world_m, int cells) {
  Opening o;
  o.id = id;
  o.viewpoint_world_m = viewpoint_world_m;
  o.cells = cells;
  return o;
}

std::vector<int> ids(const std::vector<Opening>& openings) {
  std::vector<int> out;
  for (const Opening& o : openings) out.push_back(o.id);
  return out;
}

// The door of a room next to the robot (opening 1, 3 m away, 250 cells), a shadow behind a
// post as near (opening 3, 20 cells) and a way on across the building (opening 2, 40 m away);
// the pass over the map is counted.
TEST(Openings, TouredWhenNoSurfaceViewpointIsLeftOrNoneIsNear) {
  const Eigen::Vector3d robot(0, 0, 1.5);
  const std::vector<Opening> all = {openingAt(1, {3, 0, 1.5}, 250), openingAt(2, {40, 0, 1.5}, 250),
                                    openingAt(3, {0, -4, 1.5}, 20)};
  int passes = 0;
  const auto find = [&]() -> const std::vector<Opening>& {
    ++passes;
    return all;
  };
  const double near_m = 8.0;
  const int min_cells = 100;
  // Nothing else left: every opening.
  EXPECT_EQ(ids(openingsToTour({}, robot, near_m, min_cells, find)), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(passes, 1);
  // Surface viewpoints only far away (one high above the robot counts by its horizontal
  // distance): the large near opening joins them; the far one and the small one wait.
  EXPECT_EQ(ids(openingsToTour({{20, 0, 1.5}, {0, 9, 1.5}}, robot, near_m, min_cells, find)),
            (std::vector<int>{1}));
  EXPECT_EQ(passes, 2);
  EXPECT_EQ(ids(openingsToTour({{20, 0, 1.5}}, robot, near_m, 10, find)), (std::vector<int>{1, 3}));
  EXPECT_EQ(passes, 3);
  // A surface viewpoint near the robot: no opening, and no pass over the map.
  EXPECT_TRUE(openingsToTour({{20, 0, 1.5}, {5, 5, 6.0}}, robot, near_m, min_cells, find).empty());
  EXPECT_EQ(passes, 3);
  // Radius 0: openings only once no surface viewpoint is left.
  EXPECT_TRUE(openingsToTour({{20, 0, 1.5}}, robot, 0.0, min_cells, find).empty());
  EXPECT_EQ(passes, 3);
  EXPECT_EQ(ids(openingsToTour({}, robot, 0.0, min_cells, find)), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(passes, 4);
}

// Plan after plan: openings join when no surface viewpoint is left and stay beside the surface
// viewpoints that appear again (far looks add poorly observed cells) until a plan finds none.
TEST(Openings, OnceJoinedTheyStayInTheToursUntilNoneIsFound) {
  const Eigen::Vector3d robot(0, 0, 1.5);
  std::vector<Opening> found;  // what each plan's pass over the map finds, set below
  const auto find = [&]() -> const std::vector<Opening>& { return found; };
  const std::vector<Eigen::Vector3d> surface = {{20, 0, 1.5}};
  const double near_m = 0.0;
  const int min_cells = 100;
  for (const bool stay : {true, false}) {
    SCOPED_TRACE(stay ? "stay once joined" : "plan by plan");
    found = {openingAt(1, {3, 0, 1.5}, 250), openingAt(2, {40, 0, 1.5}, 30)};
    OpeningTourMembership membership(stay);
    // Surface viewpoints left: no opening yet.
    EXPECT_TRUE(membership.select(surface, robot, near_m, min_cells, find).empty());
    EXPECT_FALSE(membership.joined());
    // None left: every opening joins.
    EXPECT_EQ(ids(membership.select({}, robot, near_m, min_cells, find)), (std::vector<int>{1, 2}));
    EXPECT_EQ(membership.joined(), stay);
    // A surface viewpoint again: they stay (and one found since joins them), or they leave.
    found.push_back(openingAt(3, {0, -4, 1.5}, 20));
    EXPECT_EQ(ids(membership.select(surface, robot, near_m, min_cells, find)),
              stay ? (std::vector<int>{1, 2, 3}) : (std::vector<int>{}));
    // None found any more: the membership ends, and surface viewpoints alone are toured.
    found.clear();
    EXPECT_TRUE(membership.select(surface, robot, near_m, min_cells, find).empty());
    EXPECT_FALSE(membership.joined());
    found = {openingAt(4, {5, 5, 1.5}, 400)};
    EXPECT_TRUE(membership.select(surface, robot, near_m, min_cells, find).empty());
    // Joining needs none left: openings that came in as near ones do not stay.
    EXPECT_EQ(ids(membership.select(surface, {5, 0, 1.5}, 8.0, min_cells, find)),
              (std::vector<int>{4}));
    EXPECT_FALSE(membership.joined());
  }
}

// The first plan of a flight, over the map of one scan, has no surface viewpoint yet: the
// openings join it and stay beside the surface viewpoints that appear next (measured better than
// waiting for the surface viewpoints to run out: see OpeningTourMembership::select).
TEST(Openings, TheFirstPlanWithoutSurfaceViewpointsKeepsThemInTheTours) {
  const Eigen::Vector3d robot(0, 0, 1.5);
  const std::vector<Opening> found = {openingAt(1, {3, 0, 1.5}, 250)};
  const auto find = [&]() -> const std::vector<Opening>& { return found; };
  const std::vector<Eigen::Vector3d> surface = {{20, 0, 1.5}};
  OpeningTourMembership membership(true);
  EXPECT_EQ(ids(membership.select({}, robot, 0.0, 100, find)), (std::vector<int>{1}));
  EXPECT_TRUE(membership.joined());
  EXPECT_EQ(ids(membership.select(surface, robot, 0.0, 100, find)), (std::vector<int>{1}));
  OpeningTourMembership plan_by_plan(false);
  EXPECT_EQ(ids(plan_by_plan.select({}, robot, 0.0, 100, find)), (std::vector<int>{1}));
  EXPECT_TRUE(plan_by_plan.select(surface, robot, 0.0, 100, find).empty());
}

// The door of the small indoor world's unseen room, reached from the start room at (14.8,
// 15.2) while the vehicle turned away: the same opening (same id) later had its viewpoint 6 m
// inside the room. Reached where it still is: a dead end; moved on: worth another look, up to
// the visit limit. Another opening is not touched by the first one's visits.
TEST(Openings, AReachedOpeningHasMovedOnOnlyOnceItsViewpointDid) {
  ReachedOpenings reached({2.0, 3});
  const Opening door = openingAt(7, {14.8, 15.2, 1.7}, 40);
  EXPECT_FALSE(reached.visited(door));
  EXPECT_FALSE(reached.movedOn(door));
  reached.markReached(7, door.viewpoint_world_m);
  EXPECT_TRUE(reached.visited(door));
  EXPECT_FALSE(reached.movedOn(door));
  EXPECT_FALSE(reached.movedOn(openingAt(7, {16.0, 14.0, 1.7}, 60)));  // 1.7 m: the same place
  const Opening grown = openingAt(7, {20.4, 12.9, 1.7}, 292);
  EXPECT_TRUE(reached.movedOn(grown));
  EXPECT_FALSE(reached.visited(openingAt(8, door.viewpoint_world_m, 40)));
  reached.markReached(7, grown.viewpoint_world_m);
  EXPECT_FALSE(reached.movedOn(grown));
  EXPECT_TRUE(reached.movedOn(door));  // back where it was first: moved again
  reached.markReached(7, door.viewpoint_world_m);
  EXPECT_FALSE(reached.movedOn(grown));  // third visit: never again
  EXPECT_FALSE(reached.movedOn(openingAt(7, {40, 0, 1.7}, 500)));
  EXPECT_TRUE(reached.visited(grown));
  EXPECT_THROW(ReachedOpenings({-1.0, 3}), std::invalid_argument);
  EXPECT_THROW(ReachedOpenings({std::nan(""), 3}), std::invalid_argument);
  EXPECT_THROW(ReachedOpenings({2.0, 0}), std::invalid_argument);
}

// Seen from the room with a 40 m range, the space behind the door leaves one large opening (the
// unseen parts of the far room) and pockets in that room the rays through the door missed,
// 10-14 cells each: not ways on, and the default cell bound leaves them out.
TEST(Openings, PocketsInTheRoomBehindADoorAreNoWayOn) {
  const OccupancyMap occ = scanned(true, 40.0);
  const std::vector<Opening> ways_on = findOpenings(occ, {0, 0, 1.5}, std::nullopt);
  ASSERT_EQ(ways_on.size(), 1u);
  EXPECT_GT(ways_on.front().cells, 500);
  EXPECT_GT(ways_on.front().viewpoint_world_m.x(), 5.3);
  OpeningConfig every;
  every.min_cells = 6;
  const std::vector<Opening> all = findOpenings(occ, {0, 0, 1.5}, std::nullopt, every);
  ASSERT_GT(all.size(), 1u);
  EXPECT_EQ(all.front().id, ways_on.front().id);
  for (size_t i = 1; i < all.size(); ++i) {
    EXPECT_LT(all[i].cells, OpeningConfig().min_cells);
    EXPECT_GT(all[i].viewpoint_world_m.x(), 5.3);  // in the room behind the door
  }
}

TEST(Openings, AClosedRoomHasNoneAndTheBoxEdgeIsNone) {
  EXPECT_TRUE(findOpenings(scanned(false), {0, 0, 1.5}, std::nullopt).empty());
  // The door open but the exploration box ending at the wall: nothing beyond it is wanted.
  const OccupancyMap occ = scanned(true);
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-6, -5, -1), Eigen::Vector3d(5.0, 5, 4));
  EXPECT_TRUE(findOpenings(occ, {0, 0, 1.5}, box).empty());
  // Beyond the search radius: not looked for.
  OpeningConfig near;
  near.search_radius_m = 3.0;
  EXPECT_TRUE(findOpenings(occ, {-4, 0, 1.5}, std::nullopt, near).empty());
}

// Openings are toured once no surface viewpoint is left, all of them: a door 100 m from the
// vehicle is one too (at a 60 m range the far ones of a large building came and went with the
// vehicle, which crossed it once per leftover).
TEST(Openings, ADoorFarFromTheVehicleIsFoundWithTheDefaults) {
  const OccupancyMap occ = scanned(true);
  const std::vector<Opening> near = findOpenings(occ, {0, 0, 1.5}, std::nullopt);
  const std::vector<Opening> far = findOpenings(occ, {-100, 0, 1.5}, std::nullopt);
  ASSERT_FALSE(near.empty());
  ASSERT_EQ(far.size(), near.size());
  EXPECT_EQ(far.front().id, near.front().id);
}

// A sensor that sees nothing more than 20 deg below the horizon (the Mid-360 pitched 15 deg)
// leaves the floor near it unknown: an opening there borders unknown space below too, and its
// viewpoint must still be a place to hover, a known-free ball, never a cell above an unseen
// floor.
TEST(Openings, ViewpointsAreKnownFreeWhenTheFloorWasNotSeen) {
  Scene scene;
  scene.room = {{-5, -4, 0}, {15, 4, 3}};
  scene.solids.push_back({{5.0, -4, 0}, {5.3, -0.6, 3}});
  scene.solids.push_back({{5.0, 0.6, 0}, {5.3, 4, 3}});
  OccupancyMap occ;
  const double min_elevation = std::sin(-20.0 * M_PI / 180.0);
  for (const Eigen::Vector3d& o :
       {Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d(3.5, 0, 0.9), Eigen::Vector3d(2, 2, 1.1)}) {
    std::vector<Eigen::Vector3d> seen;
    for (const Eigen::Vector3d& p : scene.scanSphere(o, 1.0, 8.0))
      if ((p - o).normalized().z() >= min_elevation) seen.push_back(p);
    occ.insertScan(o, seen);
  }
  const std::vector<Opening> openings = findOpenings(occ, {0, 0, 1.0}, std::nullopt);
  ASSERT_FALSE(openings.empty());
  for (const Opening& o : openings) {
    EXPECT_TRUE(occ.isKnownFree(o.viewpoint_world_m, OpeningConfig().viewpoint_clearance_m))
        << o.viewpoint_world_m.transpose();
    EXPECT_GT(o.viewpoint_world_m.z(), 0.5) << o.viewpoint_world_m.transpose();
  }
}

// A corridor seen from one end to the sensor's range: the free space 30 m out is a ray every
// half metre, no room for a known-free ball. The viewpoint is found back along the rays, where
// the space around them is known free, instead of the opening being dropped (or placed where
// nothing below was seen).
OccupancyMap corridorSeenFrom(const Eigen::Vector3d& robot) {
  Scene scene;
  scene.room = {{-1, -3, 0}, {80, 3, 3}};
  OccupancyMap occ;
  occ.insertScan(robot, scene.scanSphere(robot, 1.0, 30.0));
  return occ;
}

TEST(Openings, AFarOpeningSeenSparselyGetsAViewpointOnTheWayBack) {
  const Eigen::Vector3d robot(1.0, 0.0, 1.5);
  const OccupancyMap occ = corridorSeenFrom(robot);
  const std::vector<Opening> openings = findOpenings(occ, robot, std::nullopt);
  ASSERT_FALSE(openings.empty());
  const Opening& o = openings.front();
  EXPECT_TRUE(occ.isKnownFree(o.viewpoint_world_m, OpeningConfig().viewpoint_clearance_m));
  EXPECT_GT(o.viewpoint_world_m.x(), robot.x() + 1.0) << o.viewpoint_world_m.transpose();
  EXPECT_GT(std::cos(o.yaw_rad), 0.5) << o.yaw_rad;  // looking on down the corridor
}

// The same corridor: where the far opening is looked through from depends on the map, not on
// where the vehicle stands. Looked for on the straight way back to the vehicle, the place moved
// with it, and a vehicle that stood anywhere had "reached" it (ed21: the south-west wing, seen
// through its door, was left as a dead end by three of four guided flights).
TEST(Openings, AFarOpeningsViewpointDoesNotFollowTheVehicle) {
  const OccupancyMap occ = corridorSeenFrom({1.0, 0.0, 1.5});
  const auto farthest = [&](const Eigen::Vector3d& robot, const OpeningConfig& config) {
    const std::vector<Opening> openings = findOpenings(occ, robot, std::nullopt, config);
    EXPECT_FALSE(openings.empty());
    Eigen::Vector3d v = Eigen::Vector3d::Constant(-1e9);
    for (const Opening& o : openings)
      if (o.viewpoint_world_m.x() > v.x()) v = o.viewpoint_world_m;
    return v;
  };
  const OpeningConfig walk;
  OpeningConfig straight_back = walk;
  straight_back.max_walk_cells = 0;
  const Eigen::Vector3d here(1.0, 0.0, 1.5), there(4.0, -2.0, 1.5);
  const Eigen::Vector3d v = farthest(here, walk);
  EXPECT_TRUE(occ.isKnownFree(v, walk.viewpoint_clearance_m)) << v.transpose();
  EXPECT_GT(v.x(), 8.0) << v.transpose();
  EXPECT_LT((farthest(there, walk) - v).norm(), 1e-9);
  EXPECT_GT((farthest(there, straight_back) - farthest(here, straight_back)).norm(), 0.5);
}

// A vehicle in a corridor 1 m wide, scanned with an 8 m range: the ways on are what the rays
// left unseen along it (grazing the walls) and its rest. With 0.3 m cells no 0.5 m ball fits
// between its walls (the cells it touches span 1.2 m), a 0.36 m ball does. Without the narrow
// search the opening had no viewpoint: in ed21 (imported at 0.1 m) the flight started in a small
// room whose door and the corridor behind it held no 0.5 m ball either, and the exploration
// finished on its first plan at 2.2 % coverage.
TEST(Openings, InACorridorTooNarrowForTheFullBallTheNarrowOneIsUsed) {
  Scene scene;
  scene.room = {{-1.0, -0.35, 0.0}, {20.0, 0.65, 2.5}};  // cell boundaries at y = -0.3, 0.6
  const Eigen::Vector3d robot(0.0, 0.15, 1.35);
  OccupancyMap occ;
  occ.insertScan(robot, scene.scanSphere(robot, 1.0, 8.0));

  OpeningConfig strict;
  strict.narrow_viewpoint_clearance_m = 0.0;
  EXPECT_TRUE(findOpenings(occ, robot, std::nullopt, strict).empty());

  const OpeningConfig defaults;
  const std::vector<Opening> openings = findOpenings(occ, robot, std::nullopt, defaults);
  ASSERT_FALSE(openings.empty());
  for (const Opening& o : openings) {
    const Eigen::Vector3d& v = o.viewpoint_world_m;
    EXPECT_TRUE(occ.isKnownFree(v, defaults.narrow_viewpoint_clearance_m)) << v.transpose();
    EXPECT_FALSE(occ.isKnownFree(v, defaults.viewpoint_clearance_m)) << v.transpose();
    EXPECT_TRUE(v.x() > 0.0 && v.x() < 8.0 && v.y() > -0.35 && v.y() < 0.65) << v.transpose();
  }
}

// A handful of opening cells is a pocket, unless the sketch vouches for a place near it that no
// scan has reached: a door seen edge-on from the corridor (ed21: 9-14 cells, the room's
// guidepoint 3.5 m behind it, never entered by any flight before).
TEST(Openings, APocketIsAWayOnWhereTheSketchVouchesForAnUnseenPlaceNearIt) {
  const OccupancyMap occ = scanned(true);
  // Cells in a row across the known-free left part (x = 3.5), facing +x.
  const auto pocket = [&](int n) {
    OpeningCells cells;
    for (int i = 0; i < n; ++i) cells[occ.key({3.5, -1.0 + 0.3 * i, 1.2})] = {1.0, 0.0};
    return cells;
  };
  const OpeningConfig c;
  ASSERT_LT(8, c.min_cells);
  ASSERT_GE(8, c.vouched_min_cells);
  const Eigen::Vector3d robot(0, 0, 1.5);
  EXPECT_TRUE(findOpenings(occ, pocket(8), robot, c).empty());
  // Through the door; too far; as near, but behind the wall (y < -0.6 at x = 5-5.3).
  const std::vector<Eigen::Vector2d> near = {{6.5, 0.0}}, far = {{8.5, 0.0}},
                                     walled_off = {{5.8, -2.5}};
  const std::vector<Opening> vouched = findOpenings(occ, pocket(8), robot, c, near);
  ASSERT_EQ(vouched.size(), 1u);
  EXPECT_EQ(vouched.front().cells, 8);
  EXPECT_TRUE(occ.isKnownFree(vouched.front().viewpoint_world_m, c.viewpoint_clearance_m));
  EXPECT_TRUE(findOpenings(occ, pocket(8), robot, c, far).empty());
  EXPECT_TRUE(findOpenings(occ, pocket(8), robot, c, walled_off).empty());
  EXPECT_TRUE(findOpenings(occ, pocket(c.vouched_min_cells - 1), robot, c, near).empty());
  OpeningConfig off = c;
  off.vouched_min_cells = 0;
  EXPECT_TRUE(findOpenings(occ, pocket(8), robot, off, near).empty());
}

// The guidepoints a hypothesis maps into the world; those in space no scan reached vouch for the
// openings near them.
TEST(Openings, UnseenGuidepointsAreThoseNoScanReached) {
  const OccupancyMap occ = scanned(false);  // the right part behind the closed wall is unseen
  KnownColumns known(occ);
  const std::vector<Eigen::Vector2d> guidepoints = {{1.0, 0.0}, {11.0, 0.0}};
  const std::vector<Eigen::Vector2d> unseen = unseenPlaces(known, guidepoints);
  ASSERT_EQ(unseen.size(), 1u);
  EXPECT_LT((unseen.front() - Eigen::Vector2d(11.0, 0.0)).norm(), 1e-9);
}

// A place is unseen only where no scan reached any height of its column: in a cave that climbs,
// the drawing's free space of a lower passage lies in unknown rock at the flight height above it.
TEST(Openings, APlaceOverASeenPassageIsNotUnseen) {
  const OccupancyMap occ = scanned(false);
  const Eigen::Vector2d over_the_room(1.0, 0.0);
  ASSERT_TRUE(occ.isUnknown(occ.key(Eigen::Vector3d(1.0, 0.0, 10.0))));  // the rock above
  ASSERT_FALSE(occ.isUnknown(occ.key(Eigen::Vector3d(1.0, 0.0, 1.5))));  // the room
  KnownColumns known(occ);
  EXPECT_TRUE(unseenPlaces(known, {over_the_room}).empty());
  const OccupancyMap empty;
  KnownColumns none(empty);
  EXPECT_TRUE(unseenPlaces(none, {}).empty());
  EXPECT_EQ(unseenPlaces(none, {over_the_room}).size(), 1u);  // nothing seen at all
}

// A guidepoint 0.5 m behind the closed wall stands in an unseen cell, but the wall and the
// scanned room lie within 2 m of it: it vouches only when its own cell decides.
TEST(Openings, AnUnseenGuidepointBesideKnownWallsNeedsRoomAroundItToVouch) {
  const OccupancyMap occ = scanned(false);
  KnownColumns known(occ);
  const std::vector<Eigen::Vector2d> guidepoints = {{5.8, 0.0}, {11.0, 0.0}};
  ASSERT_EQ(unseenPlaces(known, guidepoints).size(), 2u);
  const OpeningConfig defaults;
  const std::vector<Eigen::Vector2d> roomy = unseenPlaces(
      known, guidepoints, defaults.vouched_unseen_radius_m, defaults.vouched_unseen_fraction);
  ASSERT_EQ(roomy.size(), 1u);
  EXPECT_LT((roomy.front() - Eigen::Vector2d(11.0, 0.0)).norm(), 1e-9);
  // Nothing asked of the surroundings: the radius alone, or a fraction of 0.
  EXPECT_EQ(unseenPlaces(known, guidepoints, 2.0, 0.0).size(), 2u);
  EXPECT_EQ(unseenPlaces(known, guidepoints, 0.0, 1.0).size(), 2u);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(unseenPlaces(known, {{nan, 0.0}}, 2.0, 0.9).empty());
}

TEST(Openings, BadInput) {
  OccupancyMap empty;
  EXPECT_TRUE(findOpenings(empty, {0, 0, 0}, std::nullopt).empty());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(findOpenings(scanned(true), {nan, 0, 0}, std::nullopt).empty());
  OpeningConfig bad;
  bad.min_cells = 0;
  EXPECT_THROW(findOpenings(empty, {0, 0, 0}, std::nullopt, bad), ConfigError);
  bad = {};
  bad.vouched_unseen_fraction = 1.5;
  EXPECT_THROW(findOpenings(empty, {0, 0, 0}, std::nullopt, bad), ConfigError);
  bad = {};
  bad.vouched_unseen_radius_m = -1.0;
  EXPECT_THROW(findOpenings(empty, {0, 0, 0}, std::nullopt, bad), ConfigError);
  bad = {};
  bad.max_backoff_m = -1.0;
  EXPECT_THROW(findOpenings(empty, {0, 0, 0}, std::nullopt, bad), ConfigError);
  bad = {};
  bad.narrow_viewpoint_clearance_m = 0.6;  // larger than the full clearance
  try {
    findOpenings(empty, {0, 0, 0}, std::nullopt, bad);
    ADD_FAILURE() << "no ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("openings.narrow_viewpoint_clearance_m"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace efs::planner
