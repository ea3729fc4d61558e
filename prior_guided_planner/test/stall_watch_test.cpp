// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner/stall_watch.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "efs_common/config_check.h"

namespace efs::planner {
namespace {

StallConfig patience(double patience_s, double min_gain_fraction) {
  StallConfig c;
  c.patience_s = patience_s;
  c.min_gain_fraction = min_gain_fraction;
  return c;
}

TEST(StallWatch, StallsOnlyAfterPatienceWithoutEnoughNewCells) {
  StallWatch w(patience(60.0, 0.02));
  EXPECT_FALSE(w.stalled(0.0));  // nothing recorded yet
  w.record(10.0, 5000);
  EXPECT_EQ(w.cellsToGain(), 100u);  // 2 % of 5000
  EXPECT_FALSE(w.stalled(69.9));
  EXPECT_TRUE(w.stalled(70.0));
  // Gains short of that, however many, do not count as progress...
  for (int k = 1; k <= 9; ++k) w.record(10.0 + 5.0 * k, 5000 + 10 * k);
  EXPECT_TRUE(w.stalled(70.0));
  EXPECT_EQ(w.cellsSinceLastGain(5090), 90u);
  // ... until together they reach it: the clock starts again there.
  w.record(80.0, 5100);
  ASSERT_TRUE(w.lastGainTime_s());
  EXPECT_EQ(*w.lastGainTime_s(), 80.0);
  EXPECT_EQ(w.cellsSinceLastGain(5100), 0u);
  EXPECT_EQ(w.cellsToGain(), 102u);  // the share of the new baseline
  EXPECT_FALSE(w.stalled(139.9));
  EXPECT_TRUE(w.stalled(140.0));
}

TEST(StallWatch, ACountBelowTheBaselineGainsNothing) {
  StallWatch w(patience(30.0, 0.1));
  w.record(0.0, 1000);
  w.record(5.0, 900);
  EXPECT_EQ(w.cellsSinceLastGain(900), 0u);
  w.record(10.0, 1050);  // 150 above the low reading, 50 above the baseline
  EXPECT_EQ(*w.lastGainTime_s(), 0.0);
  EXPECT_TRUE(w.stalled(30.0));
  w.record(31.0, 1100);
  EXPECT_EQ(*w.lastGainTime_s(), 31.0);
  EXPECT_FALSE(w.stalled(60.0));
}

TEST(StallWatch, ZeroPatienceNeverStalls) {
  StallWatch w(patience(0.0, 0.1));
  w.record(0.0, 10);
  EXPECT_FALSE(w.stalled(1.0e6));
}

// Before anything is seen well, any one new cell is progress.
TEST(StallWatch, AnEmptyMapNeedsOneCell) {
  StallWatch w(patience(10.0, 0.5));
  w.record(0.0, 0);
  EXPECT_EQ(w.cellsToGain(), 1u);
  w.record(5.0, 1);
  EXPECT_EQ(*w.lastGainTime_s(), 5.0);
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
  EXPECT_NE(key(patience(-1.0, 0.1)).find("last_resort_patience_s"), std::string::npos);
  EXPECT_NE(
      key(patience(std::numeric_limits<double>::quiet_NaN(), 0.1)).find("last_resort_patience_s"),
      std::string::npos);
  EXPECT_NE(key(patience(60.0, 0.0)).find("last_resort_min_gain_fraction"), std::string::npos);
  EXPECT_NE(key(patience(60.0, 1.5)).find("last_resort_min_gain_fraction"), std::string::npos);
  EXPECT_EQ(key(patience(60.0, 1.0)), "accepted");
}

}  // namespace
}  // namespace efs::planner
