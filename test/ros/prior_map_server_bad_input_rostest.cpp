// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// prior_map_server given bad input says what is wrong (naming the file or key) and stops with a
// non-zero exit; it never crashes.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include "efs_common/testing/paths.h"
#include "ros_test_utils.h"

namespace {

using efs::rostest::runNode;

void expectCleanFailure(const std::string& args, const std::string& needle) {
  const auto result = runNode("prior_map_server", args, 60);
  EXPECT_NE(result.exit_code, 0) << result.output;
  EXPECT_LT(result.exit_code, 128) << "crashed: " << result.output;
  EXPECT_NE(result.output.find(needle), std::string::npos) << result.output;
}

const std::string kSketch = efs::testing::sharedDataPath("ed21/sketch_ed21.png");

TEST(PriorMapServerBadInput, MissingSketch) {
  expectCleanFailure("_sketch_path:=/nonexistent/sketch.png", "no such file");
}
TEST(PriorMapServerBadInput, NegativeScaleGuess) {
  expectCleanFailure("_sketch_path:=" + kSketch + " _scale_guess_m_per_px:=-0.5",
                     "scale_guess_m_per_px");
}
TEST(PriorMapServerBadInput, MisspeltKey) {
  expectCleanFailure("_sketch_path:=" + kSketch + " _scale_gues_m_per_px:=0.1",
                     "scale_gues_m_per_px");
}
TEST(PriorMapServerBadInput, WrongTypeIsNamed) {
  expectCleanFailure("_sketch_path:=" + kSketch + " _prm_k_neighbours:=many", "prm_k_neighbours");
}
TEST(PriorMapServerBadInput, NotABundle) {
  expectCleanFailure("_bundle_path:=" + efs::testing::sharedDataPath("ed21/ed21.world"),
                     "not a prior bundle");
}
TEST(PriorMapServerBadInput, NothingToServe) { expectCleanFailure("", "bundle_path"); }

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "prior_map_server_bad_input_rostest");
  return RUN_ALL_TESTS();
}
