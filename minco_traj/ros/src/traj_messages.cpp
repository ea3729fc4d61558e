// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "minco_traj_ros/traj_messages.h"

#include <tf2_eigen/tf2_eigen.h>
#include <cmath>

#include "minco_traj/polytope_edges.h"

namespace efs::traj {

namespace {

geometry_msgs::Point point(const Eigen::Vector3d& p) { return tf2::toMsg(p); }

geometry_msgs::Vector3 vec(const Eigen::Vector3d& v) {
  geometry_msgs::Vector3 q;
  return tf2::toMsg(v, q);
}

visualization_msgs::Marker lineMarker(const std_msgs::Header& header, const std::string& ns,
                                      int32_t type, double width_m, float r, float g, float b) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = 0;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = width_m;
  m.color.r = r;
  m.color.g = g;
  m.color.b = b;
  m.color.a = 1.0f;
  return m;
}

}  // namespace

explore_from_sketch::PolynomialTrajectory toPolynomialTrajectory(const Trajectory& traj,
                                                                 uint32_t trajectory_id,
                                                                 const std_msgs::Header& header,
                                                                 const std::string& debug_info) {
  explore_from_sketch::PolynomialTrajectory msg;
  msg.header = header;
  msg.trajectory_id = trajectory_id;
  msg.action = explore_from_sketch::PolynomialTrajectory::ACTION_ADD;
  msg.num_order = 5;
  msg.num_segment = static_cast<uint32_t>(traj.pieceCount());
  msg.mag_coeff = 1.0;
  double rate, acc;
  traj.yaw().sample(0.0, &msg.start_yaw, &rate, &acc);
  traj.yaw().sample(std::max(traj.duration(), traj.yaw().duration()), &msg.final_yaw, &rate, &acc);
  for (int i = 0; i < traj.pieceCount(); ++i) {
    const PieceCoeffs& c = traj.pieces()[i];
    for (int k = 0; k < 6; ++k) {
      msg.coef_x.push_back(c(0, k));
      msg.coef_y.push_back(c(1, k));
      msg.coef_z.push_back(c(2, k));
    }
    msg.time.push_back(traj.durations()[i]);
    msg.order.push_back(5);
  }
  msg.debug_info = debug_info;
  return msg;
}

std::optional<Trajectory> fromPolynomialTrajectory(
    const explore_from_sketch::PolynomialTrajectory& msg, std::string* why) {
  const size_t n = msg.num_segment;
  auto fail = [&](const std::string& w) -> std::optional<Trajectory> {
    if (why) *why = w;
    return std::nullopt;
  };
  if (n == 0 || msg.time.size() != n || msg.order.size() != n)
    return fail("segment count does not match time[] / order[]");
  if (msg.coef_x.size() != 6 * n || msg.coef_y.size() != 6 * n || msg.coef_z.size() != 6 * n)
    return fail("coefficient arrays are not 6 per segment");
  if (msg.mag_coeff != 1.0) return fail("mag_coeff other than 1 is not supported");
  std::vector<PieceCoeffs> pieces(n);
  std::vector<double> durations(msg.time.begin(), msg.time.end());
  for (size_t i = 0; i < n; ++i) {
    if (msg.order[i] != 5) return fail("only order 5 segments are supported");
    if (!std::isfinite(durations[i]) || durations[i] <= 0.0)
      return fail("segment " + std::to_string(i) + " has a non-positive duration");
    for (int k = 0; k < 6; ++k) {
      pieces[i](0, k) = msg.coef_x[6 * i + k];
      pieces[i](1, k) = msg.coef_y[6 * i + k];
      pieces[i](2, k) = msg.coef_z[6 * i + k];
    }
    if (!pieces[i].allFinite()) return fail("non-finite coefficient");
  }
  Trajectory traj(std::move(pieces), std::move(durations));
  traj.setYaw(YawProfile(msg.start_yaw));
  return traj;
}

explore_from_sketch::PositionCommand toPositionCommand(const ReferenceSample& s,
                                                       uint32_t trajectory_id, uint8_t flag,
                                                       const std_msgs::Header& header) {
  explore_from_sketch::PositionCommand c;
  c.header = header;
  c.position = point(s.p_world_m);
  c.velocity = vec(s.v_world_mps);
  c.acceleration = vec(s.a_world_mps2);
  c.jerk = vec(s.j_world_mps3);
  c.yaw = s.yaw_rad;
  c.yaw_dot = s.yaw_rate_radps;
  c.trajectory_id = trajectory_id;
  c.trajectory_flag = flag;
  return c;
}

visualization_msgs::MarkerArray planMarkers(const PlanResult& plan, const Trajectory& traj,
                                            const std_msgs::Header& header, double sample_dt_s) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker clear;
  clear.header = header;
  clear.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(clear);

  auto path = lineMarker(header, "trajectory", visualization_msgs::Marker::LINE_STRIP, 0.05, 0.1f,
                         0.8f, 0.1f);
  if (!traj.empty())
    for (double t = 0.0;; t += sample_dt_s) {
      path.points.push_back(point(traj.position(std::min(t, traj.duration()))));
      if (t >= traj.duration()) break;
    }
  if (path.points.size() >= 2) out.markers.push_back(path);

  auto corridor =
      lineMarker(header, "corridor", visualization_msgs::Marker::LINE_LIST, 0.02, 0.2f, 0.4f, 1.0f);
  for (const Polytope& poly : plan.corridor.polytopes) {
    const PolytopeSkeleton s = polytopeSkeleton(poly);
    for (const auto& [u, v] : s.edges) {
      corridor.points.push_back(point(s.vertices_m[u]));
      corridor.points.push_back(point(s.vertices_m[v]));
    }
  }
  if (!corridor.points.empty()) out.markers.push_back(corridor);

  auto front = lineMarker(header, "front_end", visualization_msgs::Marker::LINE_STRIP, 0.03, 1.0f,
                          0.5f, 0.0f);
  for (const auto& p : plan.front_end.path_world_m) front.points.push_back(point(p));
  if (front.points.size() >= 2) out.markers.push_back(front);
  return out;
}

}  // namespace efs::traj
