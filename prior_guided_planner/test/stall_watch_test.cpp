// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/stall_watch.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "efs_common/config_check.h"

namespace efs::planner {
namespace {

StallConfig patience(double patience_s, int min_new_cells) {
  StallConfig c;
  c.patience_s = patience_s;
  c.min_new_cells = min_new_cells;
  return c;
}

TEST(StallWatch, StallsOnlyAfterPatienceWithoutEnoughNewCells) {
  StallWatch w(patience(60.0, 100));
  EXPECT_FALSE(w.stalled(0.0));  // nothing recorded yet
  w.record(10.0, 5000);
  EXPECT_FALSE(w.stalled(69.9));
  EXPECT_TRUE(w.stalled(70.0));
  // Gains short of min_new_cells, however many, do not count as progress...
  for (int k = 1; k <= 9; ++k) w.record(10.0 + 5.0 * k, 5000 + 10 * k);
  EXPECT_TRUE(w.stalled(70.0));
  EXPECT_EQ(w.cellsSinceLastGain(), 90u);
  // ... until together they reach it: the clock starts again there.
  w.record(80.0, 5100);
  ASSERT_TRUE(w.lastGainTime_s());
  EXPECT_EQ(*w.lastGainTime_s(), 80.0);
  EXPECT_EQ(w.cellsSinceLastGain(), 0u);
  EXPECT_FALSE(w.stalled(139.9));
  EXPECT_TRUE(w.stalled(140.0));
}

TEST(StallWatch, ACountBelowTheBaselineGainsNothing) {
  StallWatch w(patience(30.0, 100));
  w.record(0.0, 1000);
  w.record(5.0, 900);
  EXPECT_EQ(w.cellsSinceLastGain(), 0u);
  w.record(10.0, 1050);  // 150 above the low reading, 50 above the baseline
  EXPECT_EQ(*w.lastGainTime_s(), 0.0);
  EXPECT_TRUE(w.stalled(30.0));
  w.record(31.0, 1100);
  EXPECT_EQ(*w.lastGainTime_s(), 31.0);
  EXPECT_FALSE(w.stalled(60.0));
}

TEST(StallWatch, ZeroPatienceNeverStalls) {
  StallWatch w(patience(0.0, 100));
  w.record(0.0, 10);
  EXPECT_FALSE(w.stalled(1.0e6));
}

TEST(StallWatch, AbsurdSettingsAreRefusedNamingTheKey) {
  const auto key = [](const StallConfig& c) {
    try {
      StallWatch w(c);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(key(patience(-1.0, 100)).find("last_resort_patience_s"), std::string::npos);
  EXPECT_NE(
      key(patience(std::numeric_limits<double>::quiet_NaN(), 100)).find("last_resort_patience_s"),
      std::string::npos);
  EXPECT_NE(key(patience(60.0, 0)).find("last_resort_min_new_cells"), std::string::npos);
  EXPECT_EQ(key(patience(60.0, 1)), "accepted");
}

}  // namespace
}  // namespace efs::planner
