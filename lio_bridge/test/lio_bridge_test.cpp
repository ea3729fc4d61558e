// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "efs_common/config_check.h"
#include "lio_bridge/gravity_alignment.h"
#include "lio_bridge/input_monitor.h"
#include "lio_bridge/local_map.h"
#include "lio_bridge/velocity_estimator.h"

namespace efs::lio {
namespace {

OdometrySample at(double t, double x) {
  OdometrySample s;
  s.stamp_s = t;
  s.p_world_m = {x, 0, 1};
  return s;
}

TEST(InputMonitor, AcceptsSmoothFlightAndGoesStaleAfterTimeout) {
  InputMonitor m;
  EXPECT_EQ(m.health(0.0), InputHealth::kNoData);
  for (int i = 0; i < 20; ++i)
    EXPECT_EQ(m.check(at(0.01 * i, 0.03 * i)).verdict, InputMonitor::Verdict::kAccepted);
  EXPECT_EQ(m.health(0.19 + 0.1), InputHealth::kHealthy);
  EXPECT_EQ(m.health(0.19 + 0.25), InputHealth::kStale);
}

TEST(InputMonitor, RejectsNanBackwardsTimeAndBadQuaternion) {
  InputMonitor m;
  ASSERT_EQ(m.check(at(1.0, 0.0)).verdict, InputMonitor::Verdict::kAccepted);
  auto nan = at(1.1, std::numeric_limits<double>::quiet_NaN());
  EXPECT_NE(m.check(nan).reason.find("non-finite"), std::string::npos);
  EXPECT_EQ(m.check(at(0.9, 0.0)).verdict, InputMonitor::Verdict::kRejected);
  auto bad_q = at(1.2, 0.0);
  bad_q.q_world_body.coeffs() << 0, 0, 0, 2;
  EXPECT_NE(m.check(bad_q).reason.find("quaternion"), std::string::npos);
  EXPECT_EQ(m.rejectedCount(), 3);
  EXPECT_DOUBLE_EQ(m.last()->stamp_s, 1.0);  // the reference is unchanged
}

TEST(InputMonitor, ReportsAJumpOnceThenFollowsTheNewPose) {
  InputMonitor m;
  ASSERT_EQ(m.check(at(1.0, 0.0)).verdict, InputMonitor::Verdict::kAccepted);
  const auto jump = m.check(at(1.1, 5.0));  // 50 m/s
  EXPECT_EQ(jump.verdict, InputMonitor::Verdict::kJump);
  EXPECT_NE(jump.reason.find("jumped"), std::string::npos);
  EXPECT_EQ(m.jumpCount(), 1);
  EXPECT_EQ(m.check(at(1.2, 5.3)).verdict, InputMonitor::Verdict::kAccepted);
}

TEST(VelocityEstimator, RecoversConstantVelocityUnderNoise) {
  VelocityEstimator v({0.2, 100, 1});
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.005);
  const Eigen::Vector3d vel(2.0, -1.0, 0.5);
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.01 * i;
    v.add(t, vel * t + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  }
  EXPECT_LT((v.velocity() - vel).norm(), 0.1);
  VelocityEstimator empty;
  EXPECT_EQ(empty.velocity(), Eigen::Vector3d::Zero());
}

// Braking at 6 m/s^2 from 4 m/s, 100 Hz poses: the parabola has the velocity of the newest pose,
// the line that of the window's middle (ten poses span 0.09 s: 6 m/s^2 * 0.045 s = 0.27 m/s off).
TEST(VelocityEstimator, ParabolaHasNoLagUnderConstantAcceleration) {
  const Eigen::Vector3d v0(4.0, 0.0, 0.0), a(-6.0, 0.0, 0.0);
  VelocityEstimator line({0.1, 50, 1}), parabola({0.1, 50, 2});
  for (int i = 0; i <= 40; ++i) {
    const double t = 0.01 * i;
    const Eigen::Vector3d p = v0 * t + 0.5 * a * t * t;
    line.add(t, p);
    parabola.add(t, p);
  }
  const Eigen::Vector3d truth = v0 + a * 0.4;
  EXPECT_LT((parabola.velocity() - truth).norm(), 1e-6);
  EXPECT_NEAR((line.velocity() - truth).norm(), 6.0 * 0.045, 1e-6);
  // Too few samples for a parabola: the line's answer.
  VelocityEstimator early({0.1, 50, 2});
  early.add(0.0, Eigen::Vector3d::Zero());
  early.add(0.01, Eigen::Vector3d(0.02, 0, 0));
  EXPECT_LT((early.velocity() - Eigen::Vector3d(2.0, 0, 0)).norm(), 1e-9);
  VelocityEstimatorConfig bad;
  bad.fit_order = 3;
  EXPECT_THROW(VelocityEstimator{bad}, ConfigError);
}

TEST(LocalMap, DownsamplesSkipsInvalidPointsAndCropsTheWindow) {
  LocalMapConfig c;
  c.voxel_size_m = 1.0;
  c.window_radius_m = 10.0;
  c.max_range_m = 30.0;
  LocalMap map(c);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 10; ++i) pts.emplace_back(0.5f + 0.01f * i, 0.5f, 0.5f);  // one voxel
  pts.emplace_back(std::nanf(""), 0.0f, 0.0f);
  pts.emplace_back(100.0f, 0.0f, 0.0f);  // beyond max range
  pts.emplace_back(20.5f, 0.5f, 0.5f);   // in range, outside the crop window later
  EXPECT_EQ(map.insert(pts, Eigen::Vector3d::Zero()), 11u);
  EXPECT_EQ(map.size(), 2u);
  map.crop(Eigen::Vector3d::Zero());
  ASSERT_EQ(map.size(), 1u);
  EXPECT_NEAR(map.points()[0].x(), 0.545f, 1e-5);
  EXPECT_EQ(map.insert(pts, Eigen::Vector3d::Constant(std::nan(""))), 0u);
}

// Returns in runs within one voxel, alternating between voxels, with invalid returns inside a
// run, over two scans: each voxel holds the centroid of exactly its own returns.
TEST(LocalMap, EveryReturnCountsInItsOwnVoxelWhateverTheOrder) {
  LocalMapConfig c;
  c.voxel_size_m = 1.0;
  c.max_range_m = 30.0;
  LocalMap map(c);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0.05f, 0.95f);
  std::uniform_int_distribution<int> voxel(0, 3), run(1, 5);
  std::map<int, std::pair<Eigen::Vector3f, int>> expected;  // voxel -> (sum, count)
  for (int scan = 0; scan < 2; ++scan) {
    std::vector<Eigen::Vector3f> pts;
    while (pts.size() < 300) {
      const int v = voxel(rng);
      for (int i = run(rng); i > 0; --i) {
        const Eigen::Vector3f p(v + u(rng), u(rng), u(rng));
        pts.push_back(p);
        auto& [sum, n] = expected.try_emplace(v, Eigen::Vector3f::Zero(), 0).first->second;
        sum += p;
        ++n;
        if (i == 2) pts.emplace_back(std::nanf(""), 0.5f, 0.5f);
        if (i == 3) pts.emplace_back(v + 40.5f, 0.5f, 0.5f);  // beyond max_range_m
      }
    }
    map.insert(pts, Eigen::Vector3d::Zero());
  }
  ASSERT_EQ(map.size(), expected.size());
  for (const Eigen::Vector3f& centroid : map.points()) {
    const int v = static_cast<int>(std::floor(centroid.x()));
    ASSERT_TRUE(expected.count(v)) << centroid.transpose();
    const auto& [sum, n] = expected.at(v);
    EXPECT_LT((centroid - sum / static_cast<float>(n)).norm(), 1e-4f) << "voxel " << v;
  }
}

TEST(FrameDecimator, EmitsAtTheConfiguredRate) {
  FrameDecimator d(0.2);
  int frames = 0;
  for (int i = 0; i <= 3000; ++i) frames += d.due(0.01 * i);  // 30 s
  EXPECT_EQ(frames, 7);                                       // t = 0, 5, 10, ..., 30
  EXPECT_THROW(FrameDecimator(0.0), std::invalid_argument);
}

TEST(GravityAligner, LevelsATiltedStartWithoutChangingYaw) {
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitY()));
  GravityAligner g({100, 0.5});
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.02);
  // An IMU resting tilted reads gravity's reaction along the tilted frame's "up".
  const Eigen::Vector3d up_in_imu = tilt.inverse() * Eigen::Vector3d(0, 0, 9.81);
  for (int i = 0; i < 100; ++i)
    g.add(up_in_imu + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  const auto r = g.rotation();
  ASSERT_TRUE(r);
  EXPECT_LT(((*r * up_in_imu).normalized() - Eigen::Vector3d::UnitZ()).norm(), 1e-2);
  // No yaw: the x axis stays in the vertical plane it started in.
  const Eigen::Vector3d x = *r * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(x.y(), x.x()), 0.0, 0.05);
}

TEST(GravityAligner, RefusesWhenTheVehicleMoved) {
  GravityAligner g({10, 0.5});
  for (int i = 0; i < 10; ++i) g.add(Eigen::Vector3d(0, i % 2 ? 3.0 : 0.0, 9.81));
  EXPECT_TRUE(g.moved());
  EXPECT_FALSE(g.rotation());
}

}  // namespace
}  // namespace efs::lio
