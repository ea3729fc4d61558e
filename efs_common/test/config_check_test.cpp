// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/config_check.h"

#include <gtest/gtest.h>

#include <limits>

namespace efs {
namespace {

TEST(ConfigCheck, MessageNamesKeyAndRange) {
  try {
    requireInRange("prm.k_neighbours", 0, 1, 64);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("prm.k_neighbours"), std::string::npos);
    EXPECT_NE(what.find("[1, 64]"), std::string::npos);
  }
}

TEST(ConfigCheck, RejectsNanAndInfinity) {
  EXPECT_THROW(requireInRange("x", std::numeric_limits<double>::quiet_NaN(), 0.0, 1.0),
               ConfigError);
  EXPECT_THROW(requirePositive("y", std::numeric_limits<double>::infinity()), ConfigError);
  EXPECT_THROW(requirePositive("y", 0.0), ConfigError);
  EXPECT_THROW(requirePositive("y", -2.0), ConfigError);
}

TEST(ConfigCheck, AcceptsValuesInside) {
  EXPECT_NO_THROW(requireInRange("x", 0.5, 0.0, 1.0));
  EXPECT_NO_THROW(requireInRange("x", 1.0, 0.0, 1.0));
  EXPECT_NO_THROW(requirePositive("y", 1e-9));
  EXPECT_NO_THROW(requireThat(true, "z", "never"));
  EXPECT_THROW(requireThat(false, "z", "must hold"), ConfigError);
}

}  // namespace
}  // namespace efs
