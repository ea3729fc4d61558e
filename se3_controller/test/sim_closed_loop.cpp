// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The closed-loop targets against the simulator's own quadrotor (marsim_worlds), with
// both outputs: figure-eight at 3 m/s with RMS error < 0.10 m, hover within 0.05 m, recovery
// from a 1 m/s kick; AttitudeTarget output with a hover throttle the controller must learn.
#include <gtest/gtest.h>

#include "se3_controller/reference_shapes.h"
#include "sim_flight.h"

namespace efs::control {
namespace {

using testing::flySim;
using testing::Output;
using testing::stateOnReference;

const auto kNoHook = [](double, sim::QuadrotorDynamics&) {};

class SimClosedLoop : public ::testing::TestWithParam<Output> {};

TEST_P(SimClosedLoop, FigureEightAtThreeMetresPerSecond) {
  const FigureEight eight;
  Se3Controller ctrl;
  sim::QuadrotorDynamics quad(sim::QuadrotorConfig(), stateOnReference(eight.at(0.0), 9.81));
  const testing::SimFlight f = flySim(
      ctrl, quad, [&](double t) { return eight.at(t); }, 0.0, eight.period() + 1.0, 1.0, GetParam(),
      kNoHook);
  RecordProperty("rms_error_m", std::to_string(f.rms_error_m));
  RecordProperty("max_error_m", std::to_string(f.max_error_m));
  EXPECT_EQ(f.last_mode, ControlMode::kTracking);
  EXPECT_LT(f.rms_error_m, 0.10);
  EXPECT_LT(f.max_error_m, 0.25);
}

TEST_P(SimClosedLoop, HoverHoldsWithinFiveCentimetres) {
  const Eigen::Vector3d target(1, -2, 1.5);
  Se3Controller ctrl;
  sim::QuadrotorState start;
  start.p_world_m = target + Eigen::Vector3d(0.02, -0.02, 0.02);
  sim::QuadrotorDynamics quad(sim::QuadrotorConfig(), start);
  const auto ref = [&](double t) { return hoverReference(target, 0.5, t); };
  const testing::SimFlight f = flySim(ctrl, quad, ref, 0.0, 8.0, 0.0, GetParam(), kNoHook);
  EXPECT_LT(f.max_error_m, 0.05);
  EXPECT_LT((quad.state().p_world_m - target).norm(), 0.01);
  const Eigen::Vector3d x = quad.state().q_world_body * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(x.y(), x.x()), 0.5, 0.02);
}

TEST_P(SimClosedLoop, RecoversFromAVelocityKick) {
  const Eigen::Vector3d target(0, 0, 1.5);
  Se3Controller ctrl;
  sim::QuadrotorState start;
  start.p_world_m = target;
  sim::QuadrotorDynamics quad(sim::QuadrotorConfig(), start);
  const auto ref = [&](double t) { return hoverReference(target, 0.0, t); };
  flySim(ctrl, quad, ref, 0.0, 2.0, 0.0, GetParam(), kNoHook);
  bool kicked = false;
  const auto kick = [&](double, sim::QuadrotorDynamics& q) {
    if (kicked) return;
    sim::QuadrotorState s = q.state();
    s.v_world_m_s += Eigen::Vector3d(1.0, 1.0, 0.0).normalized();  // 1 m/s sideways
    q.setState(s);
    kicked = true;
  };
  const testing::SimFlight f = flySim(ctrl, quad, ref, 2.0, 4.0, 0.0, GetParam(), kick);
  EXPECT_TRUE(kicked);
  EXPECT_GT(f.max_error_m, 0.05);  // the kick did displace it
  EXPECT_LT(f.max_error_m, 0.5);   // but not far
  EXPECT_LT((quad.state().p_world_m - target).norm(), 0.02);
  EXPECT_LT(quad.state().v_world_m_s.norm(), 0.05);
}

INSTANTIATE_TEST_SUITE_P(Outputs, SimClosedLoop,
                         ::testing::Values(Output::kSo3, Output::kAttitudeTarget),
                         [](const ::testing::TestParamInfo<Output>& i) {
                           return i.param == Output::kSo3 ? "So3Command" : "AttitudeTarget";
                         });

TEST(SimClosedLoopAttitude, LearnsAnUnknownHoverThrottle) {
  sim::QuadrotorConfig qc;
  qc.hover_thrust_normalized = 0.38;  // the controller starts from 0.5
  const Eigen::Vector3d target(0, 0, 1.5);
  sim::QuadrotorState start;
  start.p_world_m = target;
  sim::QuadrotorDynamics quad(qc, start);
  Se3Controller ctrl;
  const auto ref = [&](double t) { return hoverReference(target, 0.0, t); };
  flySim(ctrl, quad, ref, 0.0, 10.0, 0.0, Output::kAttitudeTarget, kNoHook);
  EXPECT_NEAR(ctrl.hoverThrottle(), 0.38, 0.02);
  const testing::SimFlight f =
      flySim(ctrl, quad, ref, 10.0, 3.0, 0.0, Output::kAttitudeTarget, kNoHook);
  EXPECT_LT(f.max_error_m, 0.05);
}

}  // namespace
}  // namespace efs::control
