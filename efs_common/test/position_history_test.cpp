// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "efs_common/position_history.h"

namespace efs {
namespace {

TEST(PositionHistory, InterpolatesBetweenTheSamplesAroundAStamp) {
  PositionHistory h;
  for (int i = 0; i <= 100; ++i) h.add(0.01 * i, Eigen::Vector3d(4.0 * 0.01 * i, 0, 10));
  // A scan handled late still gets the position of its own stamp, not the newest one.
  const auto p = h.at(0.455);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x(), 1.82, 1e-9);
  EXPECT_NEAR(p->z(), 10.0, 1e-12);
  EXPECT_NEAR(h.at(0.5)->x(), 2.0, 1e-9);  // on a sample
  EXPECT_NEAR(h.at(1.0)->x(), 4.0, 1e-9);  // the newest
}

TEST(PositionHistory, AnswersOnlyInsideWhatItKnows) {
  PositionHistoryConfig c;
  c.keep_s = 1.0;
  c.max_gap_s = 0.2;
  c.max_extrapolation_s = 0.05;
  PositionHistory h(c);
  std::string why;
  EXPECT_FALSE(h.at(0.0, &why));
  EXPECT_NE(why.find("no odometry yet"), std::string::npos) << why;
  for (int i = 0; i <= 300; ++i) h.add(0.01 * i, Eigen::Vector3d(0.01 * i, 0, 0));
  // Older than keep_s behind the newest: dropped.
  EXPECT_FALSE(h.at(1.5, &why));
  EXPECT_NE(why.find("older than the odometry kept"), std::string::npos) << why;
  EXPECT_TRUE(h.at(2.5));
  // A little past the newest is held; further is refused.
  ASSERT_TRUE(h.at(3.04));
  EXPECT_NEAR(h.at(3.04)->x(), 3.0, 1e-9);
  EXPECT_FALSE(h.at(3.2, &why));
  EXPECT_NE(why.find("past the newest odometry"), std::string::npos) << why;
  // Odometry lost for 0.5 s: nothing is made up inside the gap.
  h.add(3.5, Eigen::Vector3d(9, 0, 0));
  EXPECT_FALSE(h.at(3.3, &why));
  EXPECT_NE(why.find("odometry gap"), std::string::npos) << why;
  EXPECT_FALSE(h.at(std::numeric_limits<double>::quiet_NaN(), &why));
  EXPECT_NE(why.find("not finite"), std::string::npos) << why;
}

TEST(PositionHistory, OutOfOrderRepeatedAndBadSamples) {
  PositionHistory h;
  EXPECT_TRUE(h.add(0.2, Eigen::Vector3d(2, 0, 0)));
  EXPECT_TRUE(h.add(0.0, Eigen::Vector3d(0, 0, 0)));  // late message: inserted in order
  EXPECT_NEAR(h.at(0.1)->x(), 1.0, 1e-12);
  EXPECT_TRUE(h.add(0.2, Eigen::Vector3d(4, 0, 0)));  // the same stamp again: replaced
  EXPECT_EQ(h.size(), 2u);
  EXPECT_NEAR(h.at(0.1)->x(), 2.0, 1e-12);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(h.add(nan, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(h.add(0.3, Eigen::Vector3d(nan, 0, 0)));
  EXPECT_EQ(h.size(), 2u);
  // The clock went back (a bag looped, a simulator restarted): the old history is dropped.
  h.add(100.0, Eigen::Vector3d(1, 1, 1));
  h.add(1.0, Eigen::Vector3d(5, 5, 5));
  EXPECT_EQ(h.size(), 1u);
  EXPECT_NEAR(h.at(1.0)->x(), 5.0, 1e-12);
}

TEST(PositionHistory, VelocityOverTheLastWindow) {
  PositionHistory h;
  EXPECT_FALSE(h.velocity(0.5));  // nothing yet
  for (int i = 0; i <= 10; ++i) h.add(0.1 * i, Eigen::Vector3d(2.0 * 0.1 * i, -1.0 * 0.1 * i, 0));
  const std::optional<Eigen::Vector3d> v = h.velocity(0.5);
  ASSERT_TRUE(v);
  EXPECT_TRUE(v->isApprox(Eigen::Vector3d(2.0, -1.0, 0.0), 1e-9)) << v->transpose();
  EXPECT_FALSE(h.velocity(5.0));  // the history does not reach back that far
  EXPECT_FALSE(h.velocity(0.0));
  EXPECT_FALSE(h.velocity(std::numeric_limits<double>::quiet_NaN()));
  h.add(2.0, Eigen::Vector3d(9, 9, 9));  // odometry lost for a second: no velocity across it
  EXPECT_FALSE(h.velocity(0.5));
}

TEST(PositionHistory, AbsurdConfigurationNamesTheKey) {
  PositionHistoryConfig c;
  c.max_gap_s = -1.0;
  try {
    PositionHistory h(c);
    FAIL() << "accepted max_gap_s = -1";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("max_gap_s"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace efs
