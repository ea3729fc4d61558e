// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "efs_common/config_check.h"
#include "efs_common/testing/config_error.h"
#include "observation_map_test_scenes.h"
#include "prior_guided_planner/occupancy_map.h"
#include "prior_guided_planner/path_length.h"

namespace efs::planner {
namespace {

using testing::Scene;

void scanFrom(OccupancyMap& occ, const Scene& s, std::initializer_list<Eigen::Vector3d> origins) {
  for (const Eigen::Vector3d& o : origins) occ.insertScan(o, s.scanSphere(o, 1.0));
}

TEST(PathLength, StraightDistanceInOpenSpace) {
  Scene s;
  s.room = {Eigen::Vector3d(-10, -10, -0.05), Eigen::Vector3d(10, 10, 5)};
  OccupancyMap occ;
  scanFrom(occ, s, {Eigen::Vector3d(0, 0, 2)});
  PathSearch ps(occ);
  const Eigen::Vector3d a(-3, 1, 1.5), b(2, -2, 2.5);
  const auto r = ps.search(a, b);
  ASSERT_TRUE(r.length_m.has_value());
  EXPECT_TRUE(r.straight);
  EXPECT_DOUBLE_EQ(*r.length_m, (b - a).norm());
  EXPECT_EQ(r.waypoints_world_m.size(), 2u);
}

TEST(PathLength, LongerAroundAWall) {
  // A wall across the room from y = -10 to y = 2: the way from one side to the other goes
  // around its end at y = 2.
  Scene s;
  s.room = {Eigen::Vector3d(-10, -10, -0.05), Eigen::Vector3d(10, 10, 4)};
  s.solids.push_back({Eigen::Vector3d(-0.15, -10.1, -0.1), Eigen::Vector3d(0.15, 2.0, 4.1)});
  OccupancyMap occ;
  scanFrom(occ, s,
           {Eigen::Vector3d(-3, 0, 2), Eigen::Vector3d(3, 0, 2), Eigen::Vector3d(0, 5, 2),
            Eigen::Vector3d(-3, -4, 2), Eigen::Vector3d(3, -4, 2)});
  PathSearch ps(occ);
  const Eigen::Vector3d a(-3, -3, 2), b(3, -3, 2);
  const auto r = ps.search(a, b);
  ASSERT_TRUE(r.length_m.has_value());
  EXPECT_FALSE(r.straight);
  // Lower bound: through the wall's end corner at (0, 2); upper bound: a generous detour
  // that keeps 1 m from the corner.
  const Eigen::Vector3d corner(0, 2, 2);
  const double lower = (corner - a).norm() + (b - corner).norm();
  const Eigen::Vector3d wide(0, 3, 2);
  const double upper = (wide - a).norm() + (b - wide).norm();
  EXPECT_GT(*r.length_m, lower);
  EXPECT_LT(*r.length_m, upper);
  // Every leg of the returned path is collision free for the vehicle (end legs: radius 0).
  const auto& w = r.waypoints_world_m;
  ASSERT_GE(w.size(), 3u);
  for (size_t i = 1; i + 2 < w.size(); ++i)
    EXPECT_TRUE(occ.segmentSafe(w[i], w[i + 1], 0.4, false));
  EXPECT_EQ(w.front(), a);
  EXPECT_EQ(w.back(), b);
}

// Around the inner corner of a 60 m L-shaped corridor: string pulling with a bounded
// look-ahead (shorten_lookahead_m) still gives nearly the shortest way, in legs no longer than
// the look-ahead, each safe for the vehicle.
TEST(PathLength, LongPathsAreShortenedWithinTheLookAhead) {
  Scene s;
  s.room = {Eigen::Vector3d(-1, -1, -0.05), Eigen::Vector3d(61, 21, 3)};
  s.solids.push_back({Eigen::Vector3d(2, 2, -0.1), Eigen::Vector3d(61.1, 21.1, 3.1)});
  OccupancyMap occ;
  for (double x = 0.5; x < 60.0; x += 4.0)
    occ.insertScan({x, 0.5, 1.5}, s.scanSphere({x, 0.5, 1.5}, 1.0));
  for (double y = 0.5; y < 20.0; y += 4.0)
    occ.insertScan({0.5, y, 1.5}, s.scanSphere({0.5, y, 1.5}, 1.0));
  PathSearchConfig c;
  c.shorten_lookahead_m = 20.0;
  PathSearch ps(occ, c);
  const Eigen::Vector3d a(58, 0.5, 1.5), b(0.5, 18, 1.5);
  const auto r = ps.search(a, b);
  ASSERT_TRUE(r.length_m.has_value());
  EXPECT_FALSE(r.straight);
  const Eigen::Vector3d corner(2.0, 2.0, 1.5);
  const double lower = (corner - a).norm() + (b - corner).norm();
  EXPECT_GT(*r.length_m, lower);
  EXPECT_LT(*r.length_m, 1.03 * lower);
  const auto& w = r.waypoints_world_m;
  ASSERT_GE(w.size(), 3u);
  for (size_t i = 0; i + 1 < w.size(); ++i)
    EXPECT_LE((w[i + 1] - w[i]).norm(), c.shorten_lookahead_m + 1e-9) << "leg " << i;
  for (size_t i = 1; i + 2 < w.size(); ++i)
    EXPECT_TRUE(occ.segmentSafe(w[i], w[i + 1], c.vehicle_radius_m, false)) << "leg " << i;
  // The same lengths from one source (the planner's per-plan query).
  const auto lengths = ps.lengthsFrom(a, {b});
  ASSERT_TRUE(lengths[0].has_value());
  EXPECT_NEAR(*lengths[0], *r.length_m, 1e-9);
}

TEST(PathLength, UnreachableIntoAClosedBox) {
  Scene outside;
  outside.room = {Eigen::Vector3d(-8, -8, -0.05), Eigen::Vector3d(8, 8, 5)};
  outside.solids = testing::hollowBox(Eigen::Vector3d(1, 1, -0.05), Eigen::Vector3d(4, 4, 3), 0.3);
  OccupancyMap occ;
  // Scans outside the box and one inside it: the inside is known free but sealed.
  scanFrom(occ, outside,
           {Eigen::Vector3d(-3, -3, 2), Eigen::Vector3d(6, 6, 2), Eigen::Vector3d(-3, 6, 2),
            Eigen::Vector3d(6, -3, 2), Eigen::Vector3d(2.5, 2.5, 1.5)});
  const Eigen::Vector3d out(-3, -3, 2), in(2.5, 2.5, 1.5), in2(2.0, 3.0, 1.5);
  ASSERT_TRUE(occ.isSafe(in, 0.4, false));
  PathSearch ps(occ);
  const auto r = ps.search(out, in);
  EXPECT_FALSE(r.length_m.has_value());
  EXPECT_FALSE(r.budget_exhausted);
  // The inside is another lattice component: known at once, without searching the outside.
  EXPECT_EQ(r.expansions, 0);
  EXPECT_FALSE(ps.connected(out, in));
  EXPECT_TRUE(ps.connected(in, in2));
  const auto inside = ps.search(in, in2);
  ASSERT_TRUE(inside.length_m.has_value());
  EXPECT_NEAR(*inside.length_m, (in2 - in).norm(), 1e-9);
  // Unknown space: a point nobody has seen is unreachable too.
  EXPECT_FALSE(ps.search(out, Eigen::Vector3d(20, 20, 2)).length_m.has_value());
  // A budget that ends early reports it (around the box to its far corner).
  const Eigen::Vector3d beyond(6, 6, 2);
  ASSERT_TRUE(ps.search(out, beyond).length_m.has_value());
  EXPECT_TRUE(ps.connected(out, beyond));
  PathSearchConfig tiny;
  tiny.max_expansions = 5;
  PathSearch small(occ, tiny);
  const auto cut = small.search(out, beyond);
  EXPECT_FALSE(cut.length_m.has_value());
  EXPECT_TRUE(cut.budget_exhausted);
  EXPECT_TRUE(small.searchFrom(out, {beyond})[0].budget_exhausted);
}

// One Dijkstra from the robot gives the same answers as one A* per target: straight where
// safe, around the wall otherwise (a lattice path of equal length may shorten differently),
// nothing into the sealed box, into unknown space, or to a NaN target.
TEST(PathLength, LengthsFromOneSourceMatchSearch) {
  Scene s;
  s.room = {Eigen::Vector3d(-10, -10, -0.05), Eigen::Vector3d(10, 10, 4)};
  s.solids.push_back({Eigen::Vector3d(-0.15, -10.1, -0.1), Eigen::Vector3d(0.15, 2.0, 4.1)});
  auto box = testing::hollowBox(Eigen::Vector3d(4, 5, -0.05), Eigen::Vector3d(7, 8, 3), 0.3);
  s.solids.insert(s.solids.end(), box.begin(), box.end());
  OccupancyMap occ;
  scanFrom(occ, s,
           {Eigen::Vector3d(-3, 0, 2), Eigen::Vector3d(3, 0, 2), Eigen::Vector3d(0, 5, 2),
            Eigen::Vector3d(-3, -4, 2), Eigen::Vector3d(3, -4, 2), Eigen::Vector3d(5.5, 6.5, 1.5)});
  const Eigen::Vector3d a(-3, -3, 2);
  const std::vector<Eigen::Vector3d> targets = {{3, -3, 2},      {-5, 4, 2},  {4, 3, 2.5},
                                                {5.5, 6.5, 1.5}, {30, 30, 2}, {std::nan(""), 0, 0},
                                                {2.5, -6, 1.5}};
  PathSearch ps(occ);
  int expansions = 0;
  const auto many = ps.lengthsFrom(a, targets, &expansions);
  ASSERT_EQ(many.size(), targets.size());
  EXPECT_GT(expansions, 0);
  int found = 0, detours = 0;
  for (size_t i = 0; i < targets.size(); ++i) {
    const auto one = ps.search(a, targets[i]);
    ASSERT_EQ(many[i].has_value(), one.length_m.has_value()) << "target " << i;
    if (!one.length_m) continue;
    ++found;
    detours += !one.straight;
    EXPECT_GE(*many[i], (targets[i] - a).norm() - 1e-9);
    EXPECT_NEAR(*many[i], *one.length_m, 0.05 * *one.length_m) << "target " << i;
  }
  EXPECT_EQ(found, 4);
  EXPECT_GE(detours, 2);              // the Dijkstra really had work to do
  EXPECT_FALSE(many[3].has_value());  // inside the sealed box
  EXPECT_FALSE(many[5].has_value());  // NaN
  EXPECT_FALSE(ps.lengthsFrom(Eigen::Vector3d(std::nan(""), 0, 0), targets)[0].has_value());
  EXPECT_TRUE(ps.lengthsFrom(a, {}).empty());
}

// Paths to many targets behind one wall share their way round its end; searchFrom() answers
// the segment tests of their string pulling once. Each path must be exactly the one the target
// gets when searched alone (a Dijkstra settles the same parents whatever else it looks for).
TEST(PathLength, TargetsSharingTheirWayGetTheirOwnPaths) {
  Scene s;
  s.room = {Eigen::Vector3d(-10, -10, -0.05), Eigen::Vector3d(10, 10, 4)};
  s.solids.push_back({Eigen::Vector3d(-0.15, -10.1, -0.1), Eigen::Vector3d(0.15, 2.0, 4.1)});
  s.solids.push_back({Eigen::Vector3d(2.0, -1.0, -0.1), Eigen::Vector3d(2.6, -0.4, 4.1)});
  OccupancyMap occ;
  scanFrom(occ, s,
           {Eigen::Vector3d(-3, 0, 2), Eigen::Vector3d(3, 0, 2), Eigen::Vector3d(0, 5, 2),
            Eigen::Vector3d(-3, -4, 2), Eigen::Vector3d(3, -4, 2), Eigen::Vector3d(6, -6, 2)});
  const Eigen::Vector3d a(-4, -5, 2);
  std::vector<Eigen::Vector3d> targets;
  for (double x = 1.5; x <= 7.5; x += 1.5)
    for (double y = -8.0; y <= -1.0; y += 1.75) targets.emplace_back(x, y, 1.5 + 0.1 * x);
  PathSearch together(occ);
  const auto all = together.searchFrom(a, targets);
  ASSERT_EQ(all.size(), targets.size());
  int detours = 0;
  for (size_t i = 0; i < targets.size(); ++i) {
    PathSearch alone(occ);
    const auto one = alone.searchFrom(a, {targets[i]});
    ASSERT_EQ(all[i].length_m.has_value(), one[0].length_m.has_value()) << "target " << i;
    if (!one[0].length_m) continue;
    detours += !one[0].straight;
    EXPECT_EQ(all[i].waypoints_world_m, one[0].waypoints_world_m) << "target " << i;
    EXPECT_EQ(*all[i].length_m, *one[0].length_m) << "target " << i;
  }
  EXPECT_GE(detours, 15);  // round the wall's end: the string pulling had shared work to do
}

// After a scan the memo forgets only what the scan could change: the answers equal those of a
// search that starts from scratch, while most of the memo survives.
TEST(PathLength, MemoSyncedScanByScanMatchesAFreshSearch) {
  Scene s;
  s.room = {Eigen::Vector3d(-15, -15, -0.05), Eigen::Vector3d(15, 15, 4)};
  s.solids.push_back({Eigen::Vector3d(-0.15, -15.1, -0.1), Eigen::Vector3d(0.15, 2.0, 4.1)});
  s.solids.push_back({Eigen::Vector3d(6, -2, -0.1), Eigen::Vector3d(7, 2, 4.1)});
  OccupancyConfig oc;
  oc.max_range_m = 8.0;  // far parts stay unknown until the robot gets there
  OccupancyMap occ(oc);
  scanFrom(occ, s, {Eigen::Vector3d(-3, 0, 2), Eigen::Vector3d(0, 5, 2)});
  PathSearch kept(occ);
  const Eigen::Vector3d a(-3, -3, 2);
  std::vector<Eigen::Vector3d> targets;
  for (double x = -12; x <= 12; x += 3)
    for (double y = -12; y <= 12; y += 4) targets.emplace_back(x, y, 2.0);
  kept.lengthsFrom(a, targets);
  for (const Eigen::Vector3d& o :
       {Eigen::Vector3d(3, 0, 2), Eigen::Vector3d(9, -5, 2), Eigen::Vector3d(-8, -9, 1.5)}) {
    const size_t memo_before = kept.memoSize();
    occ.insertScan(o, s.scanSphere(o, 1.0));
    kept.syncWithLastScan();
    EXPECT_GT(kept.memoSize(), 0u);
    EXPECT_LT(kept.memoSize(), memo_before);
    PathSearch fresh(occ);
    const auto x = kept.lengthsFrom(a, targets);
    const auto y = fresh.lengthsFrom(a, targets);
    int reachable = 0;
    for (size_t i = 0; i < targets.size(); ++i) {
      ASSERT_EQ(x[i].has_value(), y[i].has_value())
          << "target " << i << " after scan at " << o.transpose();
      if (x[i]) {
        EXPECT_DOUBLE_EQ(*x[i], *y[i]);
      }
      reachable += x[i].has_value();
    }
    EXPECT_GT(reachable, 0);
  }
}

// A serpentine maze: three walls across the room, each with a 2 m gap at alternating ends,
// and a sealed box in the last corridor. `door_closed` fills the middle wall's gap.
Scene maze(bool door_closed) {
  Scene s;
  s.room = {Eigen::Vector3d(-10, -10, -0.05), Eigen::Vector3d(10, 10, 3)};
  const double ys[3] = {-5.0, 0.0, 5.0};
  for (int i = 0; i < 3; ++i) {
    const bool gap_east = i % 2 == 0;
    const double x0 = gap_east ? -10.1 : -7.0, x1 = gap_east ? 7.0 : 10.1;
    s.solids.push_back(
        {Eigen::Vector3d(x0, ys[i] - 0.15, -0.1), Eigen::Vector3d(x1, ys[i] + 0.15, 3.1)});
  }
  if (door_closed)
    s.solids.push_back({Eigen::Vector3d(-10.1, -0.15, -0.1), Eigen::Vector3d(-7.0, 0.15, 3.1)});
  auto box = testing::hollowBox(Eigen::Vector3d(-3, 6.5, -0.05), Eigen::Vector3d(0, 9.5, 2.5), 0.3);
  s.solids.insert(s.solids.end(), box.begin(), box.end());
  return s;
}

std::vector<Eigen::Vector3d> mazeScanOrigins() {
  std::vector<Eigen::Vector3d> o;
  for (double y : {-7.5, -2.5, 2.5, 7.5})
    for (double x : {-8.5, -4.0, 0.0, 4.0, 8.5}) o.emplace_back(x, y, 1.5);
  o.emplace_back(-1.5, 8.0, 1.2);  // inside the sealed box
  return o;
}

// Component labels decide reachability exactly as a full A* does (with a budget that never
// ends): same verdict for every pair, and the Dijkstra from one point agrees with both.
TEST(PathLength, ComponentLabelsAgreeWithAStarInAMaze) {
  const Scene s = maze(false);
  OccupancyMap occ;
  for (const Eigen::Vector3d& o : mazeScanOrigins()) occ.insertScan(o, s.scanSphere(o, 1.0));
  std::vector<Eigen::Vector3d> points = mazeScanOrigins();
  points.emplace_back(-9.7, -9.7, 0.2);  // too close to the walls for the vehicle
  points.emplace_back(25, 0, 1.5);       // outside the map
  points.emplace_back(8.0, -2.5, 1.5);   // next to a scan origin
  PathSearchConfig big;
  big.max_expansions = 10000000;
  PathSearch labelled(occ, big);
  int reachable = 0, unreachable = 0, detours = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const auto from_i = labelled.lengthsFrom(points[i], points);
    for (size_t j = 0; j < points.size(); ++j) {
      if (i == j) continue;
      PathSearch fresh(occ, big);
      const PathSearchResult r = fresh.search(points[i], points[j]);
      EXPECT_FALSE(r.budget_exhausted);
      EXPECT_EQ(labelled.connected(points[i], points[j]), r.length_m.has_value())
          << i << " -> " << j;
      ASSERT_EQ(from_i[j].has_value(), r.length_m.has_value()) << i << " -> " << j;
      if (!r.length_m) {
        ++unreachable;
        EXPECT_EQ(r.expansions, 0) << "a failed search explored the map: " << i << " -> " << j;
        continue;
      }
      ++reachable;
      detours += !r.straight;
      EXPECT_NEAR(*from_i[j], *r.length_m, 0.05 * *r.length_m) << i << " -> " << j;
      EXPECT_GE(*r.length_m, (points[j] - points[i]).norm() - 1e-9);
    }
  }
  EXPECT_GT(reachable, 300);
  EXPECT_GT(unreachable, 40);  // the box, the wall corner, outside the map
  EXPECT_GT(detours, 200);     // most pairs wind through the maze
  // First corridor to the last one: through all three gaps, far longer than the straight line.
  const auto through =
      labelled.search(Eigen::Vector3d(-8.5, -7.5, 1.5), Eigen::Vector3d(8.5, 7.5, 1.5));
  ASSERT_TRUE(through.length_m.has_value());
  EXPECT_GT(*through.length_m, 45.0);
}

// A door that closes and opens again, scan by scan: the kept search (memo synced after each
// scan) gives the same answers as a fresh one, and reachability follows the door.
TEST(PathLength, ReachabilityFollowsADoorScanByScan) {
  const Scene open = maze(false), closed = maze(true);
  OccupancyMap occ;
  for (const Eigen::Vector3d& o : mazeScanOrigins()) occ.insertScan(o, open.scanSphere(o, 1.0));
  PathLengthCache cache(occ);
  PathSearch& kept = cache.search();
  const Eigen::Vector3d south(-4, -2.5, 1.5), north(-4, 2.5, 1.5), near_door(-6, -1.5, 1.5);
  const std::vector<Eigen::Vector3d> targets = {north, Eigen::Vector3d(8.5, 7.5, 1.5),
                                                Eigen::Vector3d(4, -7.5, 1.5)};
  auto check = [&](bool door_open, const char* when) {
    PathSearch fresh(occ);
    const auto x = kept.lengthsFrom(south, targets);
    const auto y = fresh.lengthsFrom(south, targets);
    for (size_t i = 0; i < targets.size(); ++i) {
      ASSERT_EQ(x[i].has_value(), y[i].has_value()) << when << ", target " << i;
      if (x[i]) {
        EXPECT_DOUBLE_EQ(*x[i], *y[i]) << when << ", target " << i;
      }
    }
    EXPECT_EQ(x[0].has_value(), door_open) << when;
    EXPECT_EQ(x[1].has_value(), door_open) << when;
    EXPECT_TRUE(x[2].has_value()) << when;  // south of the door: always reachable
    EXPECT_EQ(cache.length(1, south, 2, north).has_value(), door_open) << when;
    EXPECT_EQ(kept.connected(south, north), door_open) << when;
  };
  check(true, "before");
  // The door: 2 m of wall at the middle wall's open end, seen until its cells turn occupied.
  const double door_len = cache.length(1, south, 2, north).value();
  for (int k = 0; k < 4; ++k) {
    occ.insertScan(near_door, closed.scanSphere(near_door, 1.0));
    cache.sync();
  }
  ASSERT_TRUE(occ.isOccupied(occ.key(Eigen::Vector3d(-8.5, -0.1, 1.5))));  // its south face
  check(false, "closed");
  // Opened again: the free space returns once the door's saturated cells have taken enough of
  // the weak misses of occupied cells (3.4 / 0.1 scans).
  for (int k = 0; k < 40; ++k) {
    occ.insertScan(near_door, open.scanSphere(near_door, 1.0));
    cache.sync();
  }
  check(true, "reopened");
  EXPECT_NEAR(cache.length(1, south, 2, north).value(), door_len, 1e-6);
}

TEST(PathLength, CacheServesRepeatsAndForgetsWhatAScanChanged) {
  Scene s;
  s.room = {Eigen::Vector3d(-15, -15, -0.05), Eigen::Vector3d(15, 15, 4)};
  s.solids.push_back({Eigen::Vector3d(-0.15, -15.1, -0.1), Eigen::Vector3d(0.15, 2.0, 4.1)});
  OccupancyConfig oc;
  oc.max_range_m = 10.0;  // the room's far parts stay unknown
  OccupancyMap occ(oc);
  scanFrom(occ, s, {Eigen::Vector3d(-3, 0, 2), Eigen::Vector3d(3, 0, 2), Eigen::Vector3d(0, 5, 2)});
  PathLengthCache cache(occ);
  const Eigen::Vector3d a(-3, -3, 2), b(3, -3, 2), far(-11, 3, 2), hidden(-3, -12, 2);
  const auto l1 = cache.length(1, a, 2, b);
  ASSERT_TRUE(l1.has_value());
  EXPECT_FALSE(cache.search().search(a, b).straight);
  EXPECT_EQ(cache.stats().misses, 1u);
  EXPECT_EQ(cache.length(2, b, 1, a), l1);  // unordered pair
  EXPECT_EQ(cache.stats().hits, 1u);
  // The robot node moved: same ids, new position -> searched again.
  cache.length(1, a + Eigen::Vector3d(0.5, 0, 0), 2, b);
  EXPECT_EQ(cache.stats().misses, 2u);
  // 12 m from every scan: unknown, so unreachable, and cached as such.
  EXPECT_FALSE(cache.length(1, a, 3, hidden).has_value());
  ASSERT_TRUE(cache.length(1, a, 4, far).has_value());
  EXPECT_EQ(cache.size(), 3u);
  // A scan at the far west adds free space 2 m and more beyond `far`: the unreachable entry is
  // dropped (it may be reachable now), the paths to `far` and from a to b survive (nothing
  // turned occupied near them, no new free cell is close enough to shorten them).
  occ.insertScan(far, {Eigen::Vector3d(-14.9, 3, 2)});
  ASSERT_TRUE(occ.lastScanAddedFree());
  ASSERT_TRUE(occ.lastChangesListed());
  cache.sync();
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_EQ(cache.stats().invalidated, 1u);
  const size_t hits = cache.stats().hits;
  cache.length(1, a + Eigen::Vector3d(0.5, 0, 0), 2, b);
  EXPECT_EQ(cache.stats().hits, hits + 1);
  // The hidden place gets seen: now reachable.
  occ.insertScan(Eigen::Vector3d(-3, -6, 2), s.scanSphere(Eigen::Vector3d(-3, -6, 2), 1.0));
  cache.sync();
  EXPECT_TRUE(cache.length(1, a, 3, hidden).has_value());
  // Several scans without sync: everything is dropped.
  occ.insertScan(Eigen::Vector3d(3, -6, 2), s.scanSphere(Eigen::Vector3d(3, -6, 2), 2.0));
  occ.insertScan(Eigen::Vector3d(3, -9, 2), s.scanSphere(Eigen::Vector3d(3, -9, 2), 2.0));
  cache.sync();
  EXPECT_EQ(cache.size(), 0u);
  cache.length(1, a, 2, b);
  cache.forget(2);
  EXPECT_EQ(cache.size(), 0u);
}

// A cell that turns occupied next to a cached path drops that entry (the path is searched again
// and now goes around it); one that turns occupied metres away leaves it. The traversability
// memo kept across the scans answers as a fresh search does.
TEST(PathLength, CacheDropsAPathWhereACellTurnedOccupiedNearIt) {
  Scene s;
  s.room = {Eigen::Vector3d(-10, -10, -0.05), Eigen::Vector3d(10, 10, 4)};
  OccupancyMap occ;
  scanFrom(occ, s, {Eigen::Vector3d(-3, 0, 2), Eigen::Vector3d(3, 0, 2)});
  PathLengthCache cache(occ);
  const Eigen::Vector3d a(-4, 0.15, 2.05), b(4, 0.15, 2.05);
  const std::optional<double> straight = cache.length(1, a, 2, b);
  ASSERT_TRUE(straight.has_value());
  EXPECT_NEAR(*straight, 8.0, 1e-9);
  // Hits on a cell 3 m beside the path, then on one on it, until each turns occupied.
  for (const Eigen::Vector3d& obstacle :
       {Eigen::Vector3d(0, 3.15, 2.05), Eigen::Vector3d(0, 0.15, 2.05)}) {
    const bool on_path = obstacle.y() < 1.0;
    const size_t invalidated = cache.stats().invalidated;
    int scans = 0;
    while (!occ.isOccupied(occ.key(obstacle))) {
      occ.insertScan(Eigen::Vector3d(0, -3, 2), {obstacle});
      cache.sync();
      ASSERT_LT(++scans, 10);
    }
    ASSERT_TRUE(occ.lastChangesListed());
    EXPECT_EQ(cache.stats().invalidated, invalidated + (on_path ? 1u : 0u)) << obstacle.y();
    const std::optional<double> l = cache.length(1, a, 2, b);
    ASSERT_TRUE(l.has_value());
    if (on_path) {
      EXPECT_GT(*l, 8.0 + 1e-3);  // around the new obstacle
    } else {
      EXPECT_DOUBLE_EQ(*l, *straight);
    }
    PathSearch fresh(occ);
    const std::optional<double> f = fresh.search(a, b).length_m;
    ASSERT_TRUE(f.has_value());
    const std::optional<double> k = cache.search().search(a, b).length_m;
    ASSERT_TRUE(k.has_value());
    EXPECT_DOUBLE_EQ(*k, *f);
  }
}

// A miss from one node is answered for every node seen before with one Dijkstra; the lengths
// equal one A* per pair within what string pulling makes of an equally long lattice path.
TEST(PathLength, CacheBatchesTheMissesOfOneNode) {
  Scene s;
  s.room = {Eigen::Vector3d(-10, -10, -0.05), Eigen::Vector3d(10, 10, 4)};
  s.solids.push_back({Eigen::Vector3d(-0.15, -10.1, -0.1), Eigen::Vector3d(0.15, 2.0, 4.1)});
  OccupancyMap occ;
  scanFrom(occ, s,
           {Eigen::Vector3d(-3, 0, 2), Eigen::Vector3d(3, 0, 2), Eigen::Vector3d(0, 5, 2),
            Eigen::Vector3d(-3, -4, 2), Eigen::Vector3d(3, -4, 2)});
  PathLengthCache cache(occ);
  const std::vector<Eigen::Vector3d> p = {{-3, -3, 2}, {3, -3, 2}, {4, -7, 2},  {2, 4, 2},
                                          {-5, 5, 2},  {6, 1, 2},  {-6, -7, 2}, {30, 30, 2}};
  // Node 1 meets nodes 2..3 first (too few for a batch), then every other node with node 0.
  cache.length(1, p[1], 2, p[2]);
  cache.length(1, p[1], 3, p[3]);
  EXPECT_EQ(cache.stats().batch_searches, 0u);
  for (uint64_t i = 4; i < p.size(); ++i) cache.length(1, p[1], i, p[i]);
  const size_t misses = cache.stats().misses;
  const auto l = cache.length(0, p[0], 1, p[1]);
  EXPECT_EQ(cache.stats().batch_searches, 1u);
  for (uint64_t i = 2; i < p.size(); ++i) cache.length(i, p[i], 0, p[0]);
  EXPECT_EQ(cache.stats().misses, misses + 1);  // the rest were filled by the batch
  PathSearch ps(occ);
  ASSERT_TRUE(l.has_value());
  for (uint64_t i = 1; i < p.size(); ++i) {
    const auto batched = cache.length(0, p[0], i, p[i]);
    const auto one = ps.search(p[0], p[i]).length_m;
    ASSERT_EQ(batched.has_value(), one.has_value()) << "node " << i;
    if (one) {
      EXPECT_NEAR(*batched, *one, 0.05 * *one) << "node " << i;
    }
  }
  EXPECT_FALSE(cache.length(0, p[0], 7, p[7]).has_value());  // unknown space
  // Forgotten nodes are no batch targets any more.
  for (uint64_t i = 2; i < p.size(); ++i) cache.forget(i);
  cache.clear();
  cache.length(0, p[0], 1, p[1]);
  EXPECT_EQ(cache.stats().batch_searches, 1u);
}

// A pillar appears next to one path and far from another one: only the entry it can change is
// dropped (the scan that shows it reaches 3 m, so every changed block is near the pillar).
TEST(PathLength, CacheDropsOnlyEntriesNearWhatAScanChanged) {
  Scene s;
  s.room = {Eigen::Vector3d(-15, -15, -0.05), Eigen::Vector3d(15, 15, 4)};
  s.solids.push_back({Eigen::Vector3d(-0.15, -15.1, -0.1), Eigen::Vector3d(0.15, 8.0, 4.1)});
  OccupancyConfig oc;
  oc.max_range_m = 12.0;
  OccupancyMap occ(oc);
  for (double x : {-12.0, -6.0, 6.0, 12.0})
    for (double y : {-12.0, -6.0, 0.0, 6.0, 12.0}) scanFrom(occ, s, {Eigen::Vector3d(x, y, 2)});
  scanFrom(occ, s, {Eigen::Vector3d(0, 12, 2)});
  PathLengthCache cache(occ);
  const Eigen::Vector3d a(-6, -12, 2), b(6, -12, 2);  // around the wall's end at y = 8
  const Eigen::Vector3d c(-14, 2, 2), d(-10, 10, 2);  // straight, through the future pillar
  const auto around = cache.length(1, a, 2, b);
  ASSERT_TRUE(around.has_value());
  EXPECT_GT(*around, 2.0 * (Eigen::Vector3d(0, 8, 2) - a).norm());
  const auto past = cache.length(3, c, 4, d);
  ASSERT_TRUE(past.has_value());
  EXPECT_NEAR(*past, (d - c).norm(), 1e-9);
  Scene with_pillar = s;
  with_pillar.solids.push_back(
      {Eigen::Vector3d(-12.5, 5.5, -0.1), Eigen::Vector3d(-11.5, 6.5, 4.1)});
  const Eigen::Vector3d o(-12, 3, 2);
  for (int k = 0; k < 4; ++k) {
    occ.insertScan(o, with_pillar.scanSphere(o, 1.0, 3.0));
    cache.sync();
  }
  ASSERT_TRUE(occ.isOccupied(occ.key(Eigen::Vector3d(-12.0, 5.55, 2.0))));
  const size_t hits = cache.stats().hits;
  EXPECT_EQ(cache.length(1, a, 2, b), around);
  EXPECT_EQ(cache.stats().hits, hits + 1);
  const auto detour = cache.length(3, c, 4, d);
  EXPECT_EQ(cache.stats().hits, hits + 1);  // searched again
  ASSERT_TRUE(detour.has_value());
  EXPECT_GT(*detour, *past + 0.05);
}

TEST(PathLength, ConfigErrorsNameTheKey) {
  OccupancyMap occ;
  const auto expectKey = [&](const PathSearchConfig& c, const std::string& key) {
    efs::testing::expectConfigErrorNaming([&] { PathSearch ps(occ, c); }, key);
  };
  PathSearchConfig c;
  c.search_resolution_m = 0.0;
  expectKey(c, "path.search_resolution_m");
  c = PathSearchConfig();
  c.shorten_lookahead_m = 0.0;
  expectKey(c, "path.shorten_lookahead_m");
}

}  // namespace
}  // namespace efs::planner

#include "prior_guided_planner/observation_map_inputs.h"

namespace efs::planner {
namespace {

TEST(PlannerInputs, PathLengthFnAndObservationQueryFollowTheMaps) {
  Scene s;
  s.room = {Eigen::Vector3d(-8, -8, -0.05), Eigen::Vector3d(8, 8, 5)};
  s.solids = testing::hollowBox(Eigen::Vector3d(1, 1, -0.05), Eigen::Vector3d(4, 4, 3), 0.3);
  OccupancyMap occ;
  // Distance rules only, so that the far corner stays poorly observed (the query is what is
  // tested here, the rules in observation_map_test).
  ObservationMapConfig oc;
  oc.facing_max_distance_m = 0.0;
  ObservationMap obs(oc);
  for (const Eigen::Vector3d& o : {Eigen::Vector3d(-3, -3, 2), Eigen::Vector3d(2.5, 2.5, 1.5)}) {
    const auto pts = s.scanSphere(o, 1.0);
    occ.insertScan(o, pts);
    obs.insertScan(o, pts);
  }
  PathLengthCache cache(occ);
  std::vector<PlanViewpoint> vps(2);
  vps[0].id = 10;
  vps[0].position_world_m = Eigen::Vector3d(-1, -3, 2);
  vps[1].id = 11;
  vps[1].position_world_m = Eigen::Vector3d(2.5, 2.5, 1.5);  // sealed in the box
  const Eigen::Vector3d robot(-3, -3, 2);
  const PathLengthFn L = makePathLengthFn(cache, robot, vps);
  EXPECT_DOUBLE_EQ(L(kRobotNode, 0), 2.0);
  EXPECT_DOUBLE_EQ(L(0, kRobotNode), 2.0);
  EXPECT_EQ(L(kRobotNode, 1), kUnreachable);
  EXPECT_EQ(L(0, 1), kUnreachable);
  EXPECT_EQ(L(1, 1), 0.0);
  EXPECT_THROW(L(0, 5), std::out_of_range);
  // The same with the robot's lengths from one search.
  std::vector<double> robot_len;
  for (const auto& l :
       cache.search().lengthsFrom(robot, {vps[0].position_world_m, vps[1].position_world_m}))
    robot_len.push_back(l ? *l : kUnreachable);
  const PathLengthFn L2 = makePathLengthFn(cache, robot_len, vps);
  EXPECT_DOUBLE_EQ(L2(kRobotNode, 0), 2.0);
  EXPECT_DOUBLE_EQ(L2(0, kRobotNode), 2.0);
  EXPECT_EQ(L2(kRobotNode, 1), kUnreachable);
  EXPECT_EQ(L2(0, 1), kUnreachable);
  EXPECT_THROW(L2(kRobotNode, 2), std::out_of_range);
  EXPECT_THROW(makePathLengthFn(cache, std::vector<double>{1.0}, vps), std::invalid_argument);

  const ObservationQuery q = makeObservationQuery(obs);
  EXPECT_EQ(q(Eigen::Vector2d(-3, -3), 1.0), ObservationLevel::kWellObserved);  // floor below
  EXPECT_EQ(q(Eigen::Vector2d(30, 30), 1.0), ObservationLevel::kNone);
  // The far corner (7.5, -7.5) was seen from 10+ m only, from one direction.
  EXPECT_EQ(q(Eigen::Vector2d(7.7, -7.7), 0.3), ObservationLevel::kPoorlyObserved);
}

}  // namespace
}  // namespace efs::planner
