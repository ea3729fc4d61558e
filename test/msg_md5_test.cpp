// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Our flight-stack messages must interoperate with drones and bags that use the community's
// quadrotor_msgs / mavros_msgs, which are not packaged in Debian. ROS 1 matches publishers and
// subscribers by md5, so each of ours must hash exactly like the upstream definition. The expected
// values are the md5 sums found in the upstream packages' generated code.
#include <gtest/gtest.h>

#include <explore_from_sketch/AttitudeTarget.h>
#include <explore_from_sketch/AuxCommand.h>
#include <explore_from_sketch/PolynomialTrajectory.h>
#include <explore_from_sketch/PositionCommand.h>
#include <explore_from_sketch/SO3Command.h>

#include <string>

namespace {

template <typename M>
std::string md5() {
  return ros::message_traits::MD5Sum<M>::value();
}

TEST(MessageMd5, PositionCommandMatchesQuadrotorMsgsWithJerk) {
  // quadrotor_msgs/PositionCommand with jerk (px4ctrl, EGO-Planner v2, FUEL).
  EXPECT_EQ(md5<explore_from_sketch::PositionCommand>(), "2809eb0c779bbce5b8d66b95a05bd27b");
}

TEST(MessageMd5, PolynomialTrajectoryMatchesQuadrotorMsgs) {
  EXPECT_EQ(md5<explore_from_sketch::PolynomialTrajectory>(), "3abb6e1147f95babc52b64612c5ba5ed");
}

TEST(MessageMd5, SO3CommandMatchesQuadrotorMsgs) {
  // quadrotor_msgs/SO3Command with kR / kOm gains and AuxCommand (KumarRobotics lineage).
  EXPECT_EQ(md5<explore_from_sketch::SO3Command>(), "a466650b2633e768513aa3bf62383c86");
}

TEST(MessageMd5, AttitudeTargetMatchesMavrosMsgs) {
  EXPECT_EQ(md5<explore_from_sketch::AttitudeTarget>(), "456f3af666b22ccd0222ea053a86b548");
}

TEST(MessageMd5, FieldsSurviveSerializationRoundTrip) {
  explore_from_sketch::PositionCommand in;
  in.position.x = 1.5;
  in.jerk.z = -0.25;
  in.yaw_dot = 0.75;
  in.kx = {1.0, 2.0, 3.0};
  in.trajectory_id = 42;
  in.trajectory_flag = explore_from_sketch::PositionCommand::TRAJECTORY_STATUS_READY;
  std::vector<uint8_t> buffer(ros::serialization::serializationLength(in));
  ros::serialization::OStream out_stream(buffer.data(), buffer.size());
  ros::serialization::serialize(out_stream, in);
  explore_from_sketch::PositionCommand out;
  ros::serialization::IStream in_stream(buffer.data(), buffer.size());
  ros::serialization::deserialize(in_stream, out);
  EXPECT_DOUBLE_EQ(out.position.x, 1.5);
  EXPECT_DOUBLE_EQ(out.jerk.z, -0.25);
  EXPECT_DOUBLE_EQ(out.yaw_dot, 0.75);
  EXPECT_DOUBLE_EQ(out.kx[2], 3.0);
  EXPECT_EQ(out.trajectory_id, 42u);
  EXPECT_EQ(out.trajectory_flag, 1u);
}

}  // namespace
