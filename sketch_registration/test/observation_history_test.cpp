// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "sketch_registration/observation_history.h"

#include <gtest/gtest.h>

#include "efs_common/config_check.h"
#include "sketch_registration/scale_icp.h"

namespace efs::registration {
namespace {

using Eigen::Vector2d;

/// A wall along y = 5 from x0 to x1, a point every 0.5 m.
Points2d wallAlong(double x0, double x1, double y = 5.0) {
  Points2d out;
  for (double x = x0; x <= x1 + 1e-9; x += 0.5) out.emplace_back(x, y);
  return out;
}

TEST(ObservationHistory, WallsLeftBehindAreRememberedBeyondTheWindow) {
  ObservationHistory h;
  h.update({0, 0}, wallAlong(-20, 20), {}, 40.0);
  EXPECT_EQ(h.beyondCount(), 0u) << "everything is in the current window";
  EXPECT_EQ(h.size(), 41u) << "one point per 1 m cell";
  // 50 m on, the robot sees a new stretch; the first one now lies beyond its 40 m.
  h.update({50, 0}, wallAlong(30, 70), {}, 40.0);
  EXPECT_EQ(h.size(), 82u);
  for (const Vector2d& p : h.beyond()) EXPECT_GT((p - Vector2d(50, 0)).norm(), 40.0);
  // A cell keeps the last of its points (x.5); those with x < 10.3 lie beyond 40 m.
  EXPECT_EQ(h.beyondCount(), 30u);
}

TEST(ObservationHistory, PassageSeenWhereAWallWasForgetsIt) {
  ObservationHistory h;
  h.update({0, 0}, wallAlong(-5, 5), {}, 40.0);
  ASSERT_EQ(h.size(), 11u);
  // Seen again from elsewhere: two of the columns are passage (a car first taken for a wall).
  h.update({1, 0}, {}, {{0.6, 5.0}, {3.4, 5.1}}, 40.0);
  EXPECT_EQ(h.size(), 9u);
  // Contrast: a frame that merely does not see the wall (out of its height band) keeps it.
  h.update({2, 0}, {}, {}, 40.0);
  EXPECT_EQ(h.size(), 9u);
  // Passage farther than forget_radius_m from every remembered point erases nothing.
  h.update({2, 0}, {}, {{0.5, 3.0}}, 40.0);
  EXPECT_EQ(h.size(), 9u);
}

TEST(ObservationHistory, ForgetsBeyondItsRadiusAndThinsEvenly) {
  ObservationHistoryConfig config;
  config.radius_m = 100.0;
  config.max_points = 10;
  ObservationHistory h(config);
  h.update({0, 0}, wallAlong(-20, 20), {}, 40.0);
  h.update({60, 0}, wallAlong(50, 70), {}, 10.0);
  EXPECT_EQ(h.beyond().size(), 10u) << "thinned to max_points";
  EXPECT_GT(h.beyondCount(), 10u);
  h.update({200, 0}, {}, {}, 10.0);
  EXPECT_EQ(h.size(), 0u) << "all farther than radius_m";
  ObservationHistoryConfig off;
  off.enabled = false;
  ObservationHistory none(off);
  none.update({0, 0}, wallAlong(-20, 20), {}, 1.0);
  EXPECT_EQ(none.size(), 0u);
}

TEST(ObservationHistory, ConfigNamesTheKey) {
  ObservationHistoryConfig config;
  config.forget_radius_m = 2.0;  // not below cell_m
  try {
    config.validate();
    FAIL() << "accepted forget_radius_m >= cell_m";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("history_forget_radius_m"), std::string::npos);
  }
}

TEST(HistoryFit, ExplainedAndOutsideTheDrawing) {
  // A 20 m corridor drawn (walls y = 0 and y = 4, x in [0, 20]).
  Points2d sketch = wallAlong(0, 20, 0.0);
  const Points2d upper = wallAlong(0, 20, 4.0);
  sketch.insert(sketch.end(), upper.begin(), upper.end());
  const ScaleIcp icp(sketch, ScaleIcpConfig{});
  Points2d remembered = wallAlong(2, 10, 0.0);                           // 17 on a drawn wall
  for (double x = 2; x < 10; x += 1.0) remembered.emplace_back(x, 2.0);  // 8 in the corridor
  remembered.emplace_back(10.0, 40.0);  // far outside the drawing: not inside its extent
  const HistoryFit fit = icp.historyFit(Sim2(), remembered);
  EXPECT_EQ(fit.points, 26);
  EXPECT_EQ(fit.inside, 25);
  EXPECT_EQ(fit.explained, 17);
  EXPECT_NEAR(fit.inlierRatio(), 17.0 / 25.0, 1e-12);
  // The same walls under a 2 m shift lie in the corridor or beside it: few explained.
  const HistoryFit shifted = icp.historyFit(Sim2(0.0, 1.0, Vector2d(0.0, 2.0)), remembered);
  EXPECT_LT(shifted.inlierRatio(), 0.5);
  // Without remembered walls inside the drawing nothing speaks against a placement.
  EXPECT_DOUBLE_EQ(icp.historyFit(Sim2(), {}).inlierRatio(), 1.0);
}

}  // namespace
}  // namespace efs::registration
