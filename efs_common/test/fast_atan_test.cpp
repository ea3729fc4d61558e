// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/fast_atan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace efs {
namespace {

TEST(FastAtan, Atan2WithinItsBoundAllAround) {
  double worst = 0.0;
  for (int i = 0; i < 100000; ++i) {
    const double a = -M_PI + 2.0 * M_PI * (i + 0.5) / 100000.0;
    for (const double r : {1e-3, 0.7, 13.0, 4e5}) {
      const double y = r * std::sin(a), x = r * std::cos(a);
      worst = std::max(worst, std::abs(fastAtan2(y, x) - std::atan2(y, x)));
    }
  }
  EXPECT_LT(worst, 5e-8);
}

TEST(FastAtan, Atan2OnTheAxesAndDiagonals) {
  for (const double r : {1e-300, 1.0, 1e300}) {
    EXPECT_DOUBLE_EQ(fastAtan2(0.0, r), 0.0);
    EXPECT_NEAR(fastAtan2(r, 0.0), 0.5 * M_PI, 5e-8);
    EXPECT_NEAR(fastAtan2(-r, 0.0), -0.5 * M_PI, 5e-8);
    EXPECT_NEAR(fastAtan2(0.0, -r), M_PI, 5e-8);
    EXPECT_NEAR(fastAtan2(-0.0, -r), -M_PI, 5e-8);
    EXPECT_NEAR(fastAtan2(r, r), 0.25 * M_PI, 5e-8);
    EXPECT_NEAR(fastAtan2(-r, -r), -0.75 * M_PI, 5e-8);
  }
  EXPECT_EQ(fastAtan2(0.0, 0.0), 0.0);
}

TEST(FastAtan, AtanWithinItsBoundAndOdd) {
  double worst = 0.0;
  for (int i = -200000; i <= 200000; ++i) {
    const double x = i * 1e-4 * std::abs(i) * 1e-4;  // denser near 0, out to +-400
    worst = std::max(worst, std::abs(fastAtan(x) - std::atan(x)));
    EXPECT_EQ(fastAtan(-x), -fastAtan(x));
  }
  EXPECT_LT(worst, 5e-8);
}

TEST(FastAtan, NonFiniteInputFallsBackToTheLibrary) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(fastAtan2(nan, 1.0)));
  EXPECT_TRUE(std::isnan(fastAtan2(1.0, nan)));
  EXPECT_TRUE(std::isnan(fastAtan(nan)));
  EXPECT_DOUBLE_EQ(fastAtan(inf), 0.5 * M_PI);
  EXPECT_DOUBLE_EQ(fastAtan2(1.0, -inf), M_PI);
  EXPECT_DOUBLE_EQ(fastAtan2(inf, inf), 0.25 * M_PI);
}

}  // namespace
}  // namespace efs
