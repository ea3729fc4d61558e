// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "exploration_mission/registration_log.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "efs_common/testing/text_lines.h"

namespace efs::mission {
namespace {

TEST(RegistrationLog, OneLinePerFrameWithTheBestHypothesisAndTheQuotedReason) {
  HypothesisRecord waiting;
  waiting.time_s = 5.0;
  waiting.status = registration::RegistrationStatus::kAllRejectedByFitness;
  waiting.message = R"(8 transforms refined, none with F below 0.6 m, "see" above)";
  HypothesisRecord found;
  found.time_s = 10.0;
  found.status = registration::RegistrationStatus::kOk;
  found.message = "2 hypotheses; best F = 0.12 m";
  registration::Hypothesis best;
  best.id = 3;
  best.fitness_m = 0.12;
  best.confidence = 0.75;
  best.coverage = 0.9;
  best.T_world_sketch = Sim2(0.5, 1.6, Eigen::Vector2d(-4.0, 7.5));
  best.T_world_sketch.stretch = 1.05;
  best.T_world_sketch.stretch_axis_rad = 0.25;
  found.hypotheses = {best, registration::Hypothesis{}};

  std::ostringstream out;
  writeRegistrationLog(out, {waiting, found});
  const std::vector<std::string> l = testing::textLines(out.str());
  ASSERT_EQ(l.size(), 3u);
  EXPECT_EQ(l[0].rfind("time_s,status,hypotheses,best_id,", 0), 0u);
  EXPECT_EQ(l[1], R"(5,all_rejected_by_fitness,0,,,,,,,,,,,,"8 transforms refined, none with F )"
                  R"(below 0.6 m, ""see"" above")");
  EXPECT_EQ(
      l[2],
      R"(10,ok,2,3,0.12,0.75,0.9,1.6,0.5,-4,7.5,0,1.05,0.25,"2 hypotheses; best F = 0.12 m")");
}

}  // namespace
}  // namespace efs::mission
