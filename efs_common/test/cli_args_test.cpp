// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/cli_args.h"

#include <gtest/gtest.h>

#include <cmath>

namespace efs {
namespace {

TEST(CliArgs, ParsesValuesFlagsAndInlineValues) {
  const char* argv[] = {"tool", "--sketch", "a.png", "--scale=0.1", "--verbose", "extra"};
  const CliArgs args(6, argv, {"sketch", "scale"}, {"verbose"});
  EXPECT_EQ(args.required("sketch"), "a.png");
  EXPECT_DOUBLE_EQ(args.number("scale", 1.0), 0.1);
  EXPECT_TRUE(args.flag("verbose"));
  EXPECT_EQ(args.positional().size(), 1u);
  EXPECT_EQ(args.str("missing", "dflt"), "dflt");
}

TEST(CliArgs, ErrorsNameTheOption) {
  const char* unknown[] = {"tool", "--skecth", "a.png"};
  try {
    CliArgs(3, unknown, {"sketch"});
    FAIL();
  } catch (const CliError& e) {
    EXPECT_NE(std::string(e.what()).find("--skecth"), std::string::npos);
  }
  const char* no_value[] = {"tool", "--sketch"};
  EXPECT_THROW(CliArgs(2, no_value, {"sketch"}), CliError);
  const char* bad_number[] = {"tool", "--scale", "abc"};
  const CliArgs args(3, bad_number, {"scale"});
  EXPECT_THROW(args.number("scale", 1.0), CliError);
  EXPECT_THROW(args.required("other"), CliError);
}

TEST(CliArgs, NanPassesThroughForConfigValidation) {
  const char* argv[] = {"tool", "--scale", "nan", "--n", "2.5"};
  const CliArgs args(5, argv, {"scale", "n"});
  EXPECT_TRUE(std::isnan(args.number("scale", 1.0)));
  EXPECT_THROW(args.integer("n", 1), CliError);
}

}  // namespace
}  // namespace efs
