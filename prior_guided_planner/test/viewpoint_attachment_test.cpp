// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include "efs_common/config_check.h"
#include "prior_guided_planner/viewpoint_attachment.h"

namespace efs::planner {
namespace {

GuidepointPrior threeGuidepoints() {
  GuidepointPrior g;
  g.ids = {10, 11, 12};
  g.positions_sketch_m = {{0, 0}, {30, 0}, {100, 0}};
  g.prm_distance_m = CostMatrix(3, 0.0);
  return g;
}

PlanViewpoint vp(int id, double x, double y) {
  PlanViewpoint v;
  v.id = id;
  v.position_world_m = {x, y, 1.5};
  return v;
}

// Hypothesis: scale 2, no rotation, shift (10, 5): guidepoints at (10,5), (70,5), (210,5).
Hypothesis hyp() { return Hypothesis{1, Sim2(0.0, 2.0, {10.0, 5.0}), 0.9}; }

TEST(ViewpointAttachment, AttachRuleAndTransform) {
  const std::vector<PlanViewpoint> vps = {
      vp(0, 12, 5),   // 2 m from G0 -> G0
      vp(1, 40, 5),   // 30 m from G0 and G1: beyond rho -> none
      vp(2, 65, 5),   // 5 m from G1 -> G1
      vp(3, 24, 5),   // 14 m from G0, 46 from G1 -> G0
      vp(4, 205, 40)  // 35 m from G2: beyond rho -> none
  };
  const HypothesisAttachment a =
      attachViewpoints(hyp(), threeGuidepoints(), vps, nullptr, std::nullopt, AttachmentConfig{});
  EXPECT_NEAR(a.guidepoints_world_m[1].x(), 70.0, 1e-12);
  EXPECT_NEAR(a.guidepoints_world_m[2].x(), 210.0, 1e-12);
  EXPECT_EQ(a.attached_to, (std::vector<int>{0, -1, 1, 0, -1}));
  EXPECT_EQ(a.attached[0], (std::vector<int>{0, 3}));
  EXPECT_EQ(a.attached[1], (std::vector<int>{2}));
  EXPECT_TRUE(a.attached[2].empty());
  EXPECT_EQ(a.states[0], GuidepointState::kExploring);
  EXPECT_EQ(a.states[1], GuidepointState::kExploring);
  EXPECT_EQ(a.states[2], GuidepointState::kUnexplored);
}

TEST(ViewpointAttachment, NearestOtherGuidepointBoundsTheRadius) {
  AttachmentConfig cfg;
  cfg.rho_m = 100.0;
  // Midway between G0 (10,5) and G1 (70,5): a tie attaches to none; 1 m off -> nearer one.
  const std::vector<PlanViewpoint> vps = {vp(0, 40, 5), vp(1, 41, 5), vp(2, 39, 30)};
  const HypothesisAttachment a =
      attachViewpoints(hyp(), threeGuidepoints(), vps, nullptr, std::nullopt, cfg);
  EXPECT_EQ(a.attached_to, (std::vector<int>{-1, 1, 0}));
}

TEST(ViewpointAttachment, StatesFromObservations) {
  const std::vector<PlanViewpoint> vps = {vp(0, 12, 5)};
  // Well observed around G1, only poorly observed around G2.
  const ObservationQuery obs = [](const Eigen::Vector2d& c, double r) {
    EXPECT_DOUBLE_EQ(r, 5.0);
    if (std::abs(c.x() - 70.0) < 1e-9) return ObservationLevel::kWellObserved;
    if (std::abs(c.x() - 210.0) < 1e-9) return ObservationLevel::kPoorlyObserved;
    return ObservationLevel::kNone;
  };
  const HypothesisAttachment a =
      attachViewpoints(hyp(), threeGuidepoints(), vps, obs, std::nullopt, AttachmentConfig{});
  EXPECT_EQ(a.states[0], GuidepointState::kExploring);  // attached wins over observations
  EXPECT_EQ(a.states[1], GuidepointState::kExplored);
  EXPECT_EQ(a.states[2], GuidepointState::kUnexplored);
}

// seen_fraction: G0's free space is sampled at x = -4 .. 5 sketch m (world 2 .. 20), G1's at
// 26 .. 35 (world 62 .. 80); a viewpoint is attached to each. All of G0's samples and 8 of G1's
// 10 lie under well observed surface: with 0.9, G0 is explored despite its viewpoint, G1 (80 %)
// still exploring; with 0.8 both are explored; with 0 (the paper) both exploring.
TEST(ViewpointAttachment, AGuidepointWhoseFreeSpaceIsSeenIsExploredWhateverIsLeft) {
  GuidepointPrior prior = threeGuidepoints();
  prior.predicted_free_cell_m = 1.0;
  for (int k = 0; k < 10; ++k) {
    prior.predicted_free_sketch_m.emplace_back(-4.0 + k, 0.0);
    prior.predicted_free_sketch_m.emplace_back(26.0 + k, 0.0);
  }
  const std::vector<PlanViewpoint> vps = {vp(0, 12, 5), vp(1, 65, 5)};
  const ObservationQuery obs = [](const Eigen::Vector2d& c, double r) {
    if (r >= 5.0) return ObservationLevel::kNone;  // the paper's influence radius: nothing
    EXPECT_DOUBLE_EQ(r, 1.0);                      // half a sample cell, in world metres (scale 2)
    return c.x() < 77.0 ? ObservationLevel::kWellObserved : ObservationLevel::kNone;
  };
  const auto states = [&](double fraction) {
    AttachmentConfig cfg;
    cfg.seen_fraction = fraction;
    return attachViewpoints(hyp(), prior, vps, obs, std::nullopt, cfg).states;
  };
  EXPECT_EQ(states(0.9)[0], GuidepointState::kExplored);
  EXPECT_EQ(states(0.9)[1], GuidepointState::kExploring);
  EXPECT_EQ(states(0.8)[1], GuidepointState::kExplored);
  EXPECT_EQ(states(0.0)[0], GuidepointState::kExploring);
  EXPECT_EQ(states(0.0)[1], GuidepointState::kExploring);
  // G2 has no samples of its own: the rule leaves it to the paper's states.
  EXPECT_EQ(states(0.9)[2], GuidepointState::kUnexplored);
  AttachmentConfig bad;
  bad.seen_fraction = 1.5;
  EXPECT_THROW(bad.validate(), ConfigError);
}

// seen_keep_radius_m: G0's free space is all seen, but its viewpoint (12, 5) is 4 m from a
// robot at (16, 5): it stays exploring while the robot is that near, and turns explored once
// the robot is 10 m away, or when no robot position is given.
TEST(ViewpointAttachment, ASeenGuidepointWithAViewpointBesideTheRobotKeepsExploring) {
  GuidepointPrior prior = threeGuidepoints();
  prior.predicted_free_cell_m = 1.0;
  for (int k = 0; k < 10; ++k) prior.predicted_free_sketch_m.emplace_back(-4.0 + k, 0.0);
  const std::vector<PlanViewpoint> vps = {vp(0, 12, 5)};
  const ObservationQuery obs = [](const Eigen::Vector2d&, double r) {
    return r < 5.0 ? ObservationLevel::kWellObserved : ObservationLevel::kNone;
  };
  AttachmentConfig cfg;
  cfg.seen_fraction = 0.9;
  cfg.seen_keep_radius_m = 5.0;
  const auto stateOfG0 = [&](const std::optional<Eigen::Vector2d>& robot) {
    return attachViewpoints(hyp(), prior, vps, obs, std::nullopt, cfg, robot).states[0];
  };
  EXPECT_EQ(stateOfG0(Eigen::Vector2d(16, 5)), GuidepointState::kExploring);
  EXPECT_EQ(stateOfG0(Eigen::Vector2d(22, 5)), GuidepointState::kExplored);
  EXPECT_EQ(stateOfG0(std::nullopt), GuidepointState::kExplored);
  cfg.seen_keep_radius_m = 0.0;  // off: the seen rule alone
  EXPECT_EQ(stateOfG0(Eigen::Vector2d(16, 5)), GuidepointState::kExplored);
  AttachmentConfig bad;
  bad.seen_keep_radius_m = -1.0;
  EXPECT_THROW(bad.validate(), ConfigError);
}

TEST(ViewpointAttachment, GuidepointsFarOutsideTheBoundsTakeNoPart) {
  const Eigen::AlignedBox2d bounds(Eigen::Vector2d(0, 0), Eigen::Vector2d(100, 50));
  // G2 lands at x = 210, 110 m outside: kOutside; a viewpoint next to it attaches to nothing
  // (and not to G1 either: it is 140 m away).
  const std::vector<PlanViewpoint> vps = {vp(0, 205, 5), vp(1, 12, 5)};
  const HypothesisAttachment a =
      attachViewpoints(hyp(), threeGuidepoints(), vps, nullptr, bounds, AttachmentConfig{});
  EXPECT_EQ(a.states[2], GuidepointState::kOutside);
  EXPECT_EQ(a.states[1], GuidepointState::kUnexplored);
  EXPECT_EQ(a.attached_to, (std::vector<int>{-1, 0}));
  EXPECT_STREQ(toString(a.states[2]), "outside");
}

TEST(ViewpointAttachment, RejectsUnusableHypothesesWithAReason) {
  Hypothesis h = hyp();
  h.T_world_sketch.scale = std::nan("");
  ASSERT_TRUE(hypothesisDefect(h).has_value());
  EXPECT_NE(hypothesisDefect(h)->find("not finite"), std::string::npos);
  EXPECT_THROW(attachViewpoints(h, threeGuidepoints(), {}, nullptr, std::nullopt, {}),
               std::invalid_argument);
  h = hyp();
  h.T_world_sketch.scale = 0.0;
  EXPECT_NE(hypothesisDefect(h)->find("not positive"), std::string::npos);
  h.T_world_sketch.scale = -2.0;
  EXPECT_NE(hypothesisDefect(h)->find("not positive"), std::string::npos);
  h = hyp();
  h.T_world_sketch.stretch = 0.9;  // exp of a negative log_stretch off the wire
  EXPECT_NE(hypothesisDefect(h)->find("stretch 0.9"), std::string::npos);
  h.T_world_sketch.stretch = 1.06;
  EXPECT_FALSE(hypothesisDefect(h).has_value());
  h = hyp();
  h.confidence = -0.1;
  EXPECT_TRUE(hypothesisDefect(h).has_value());
  EXPECT_FALSE(hypothesisDefect(hyp()).has_value());
  AttachmentConfig cfg;
  cfg.rho_m = 0.0;
  try {
    cfg.validate();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("attachment.rho_m"), std::string::npos);
  }
}

TEST(ViewpointAttachment, MalformedPriorIsRejected) {
  GuidepointPrior g = threeGuidepoints();
  g.prm_distance_m = CostMatrix(2);
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = threeGuidepoints();
  g.prm_distance_m(0, 1) = std::nan("");
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = threeGuidepoints();
  g.prm_distance_m(0, 1) = kUnreachable;  // unreachable is legal
  EXPECT_NO_THROW(g.validate());
}

}  // namespace
}  // namespace efs::planner
