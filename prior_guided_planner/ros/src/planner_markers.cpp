// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_guided_planner_ros/planner_markers.h"

#include <geometry_msgs/Point.h>
#include <std_msgs/ColorRGBA.h>

#include <cmath>
#include <string>

namespace efs::planner {
namespace {

std_msgs::ColorRGBA rgba(float r, float g, float b, float a = 1.0f) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

// A fixed palette, cycled by index: distinct neighbouring colours for groups and clusters.
std_msgs::ColorRGBA palette(int i) {
  static const float k[10][3] = {
      {0.90f, 0.10f, 0.10f}, {0.10f, 0.60f, 0.90f}, {0.20f, 0.80f, 0.20f}, {0.95f, 0.60f, 0.10f},
      {0.60f, 0.20f, 0.80f}, {0.10f, 0.80f, 0.75f}, {0.85f, 0.30f, 0.60f}, {0.55f, 0.45f, 0.20f},
      {0.30f, 0.30f, 0.95f}, {0.75f, 0.75f, 0.10f}};
  const int j = ((i % 10) + 10) % 10;
  return rgba(k[j][0], k[j][1], k[j][2]);
}

visualization_msgs::Marker base(const std_msgs::Header& header, const std::string& ns, int type,
                                double scale_m) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = ns;
  m.id = 0;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = scale_m;
  m.color = rgba(1.0f, 1.0f, 1.0f);
  return m;
}

std_msgs::ColorRGBA stateColour(GuidepointState s) {
  switch (s) {
    case GuidepointState::kUnexplored:
      return rgba(0.6f, 0.6f, 0.6f);
    case GuidepointState::kExploring:
      return rgba(1.0f, 0.55f, 0.0f);
    case GuidepointState::kExplored:
      return rgba(0.1f, 0.75f, 0.2f);
    case GuidepointState::kOutside:
      return rgba(0.3f, 0.3f, 0.3f, 0.4f);
  }
  return rgba(1.0f, 1.0f, 1.0f);
}

}  // namespace

geometry_msgs::Point toPointMsg(const Eigen::Vector3d& p) {
  geometry_msgs::Point q;
  q.x = p.x();
  q.y = p.y();
  q.z = p.z();
  return q;
}

visualization_msgs::MarkerArray plannerMarkers(const ExplorationManager& mgr,
                                               const RobotPose& robot,
                                               const std_msgs::Header& header,
                                               const PlannerMarkerOptions& opt) {
  using visualization_msgs::Marker;
  visualization_msgs::MarkerArray out;
  Marker clear;
  clear.header = header;
  clear.action = Marker::DELETEALL;
  out.markers.push_back(clear);

  // Viewpoints coloured by group (isolated ones grey); all one colour without groups.
  const std::vector<PlanViewpoint>& vps = mgr.viewpoints();
  const PlanningResult* plan = mgr.lastPlan();
  Marker vp = base(header, "viewpoints", Marker::SPHERE_LIST, 0.4);
  std::vector<std_msgs::ColorRGBA> vp_colour(vps.size(), rgba(0.2f, 0.5f, 1.0f));
  if (plan)
    for (size_t g = 0; g < plan->groups.size(); ++g)
      for (int i : plan->groups[g].viewpoints)
        if (i >= 0 && i < static_cast<int>(vps.size()))
          vp_colour[i] =
              plan->groups[g].isolated() ? rgba(0.5f, 0.5f, 0.5f) : palette(static_cast<int>(g));
  for (size_t i = 0; i < vps.size(); ++i) {
    vp.points.push_back(toPointMsg(vps[i].position_world_m));
    vp.colors.push_back(vp_colour[i]);
  }
  if (!vp.points.empty()) out.markers.push_back(vp);

  // Guidepoints under the active hypothesis, coloured by state, and the selected sequence.
  if (const HypothesisAttachment* a = mgr.activeAttachment()) {
    Marker gp = base(header, "guidepoints", Marker::SPHERE_LIST, 0.8);
    for (size_t j = 0; j < a->guidepoints_world_m.size(); ++j) {
      const Eigen::Vector2d& g = a->guidepoints_world_m[j];
      gp.points.push_back(toPointMsg({g.x(), g.y(), opt.guidepoint_z_m}));
      gp.colors.push_back(stateColour(a->states[j]));
    }
    if (!gp.points.empty()) out.markers.push_back(gp);
    Marker seq = base(header, "guidepoint_sequence", Marker::LINE_STRIP, 0.15);
    seq.color = rgba(1.0f, 0.2f, 0.8f);
    seq.points.push_back(toPointMsg(robot.position_world_m));
    for (const Eigen::Vector2d& g : mgr.activeGuidepointSequence())
      seq.points.push_back(toPointMsg({g.x(), g.y(), opt.guidepoint_z_m}));
    if (seq.points.size() >= 2) out.markers.push_back(seq);
  }

  // The local tour from the robot, and the goal as an arrow along its yaw.
  const ExplorationTarget& t = mgr.target();
  Marker tour = base(header, "tour", Marker::LINE_STRIP, 0.1);
  tour.color = rgba(0.1f, 0.9f, 0.9f);
  tour.points.push_back(toPointMsg(robot.position_world_m));
  for (const Eigen::Vector3d& p : t.tour_world_m) tour.points.push_back(toPointMsg(p));
  if (tour.points.size() >= 2) out.markers.push_back(tour);
  if (t.has_goal) {
    Marker goal = base(header, "goal", Marker::ARROW, 1.0);
    goal.scale.y = goal.scale.z = 0.25;
    goal.color = rgba(1.0f, 0.9f, 0.0f);
    goal.pose.position = toPointMsg(t.goal_world_m);
    goal.pose.orientation.z = std::sin(0.5 * t.goal_yaw_rad);
    goal.pose.orientation.w = std::cos(0.5 * t.goal_yaw_rad);
    out.markers.push_back(goal);
  }

  // Frontier cells coloured by cluster.
  const FrontierClusterer& fc = mgr.frontierClusters();
  const double res = mgr.observationMap().resolution();
  size_t total = 0;
  for (const auto& [id, c] : fc.clusters()) total += c.cells.size();
  const size_t stride = total > opt.max_frontier_cells && opt.max_frontier_cells > 0
                            ? (total + opt.max_frontier_cells - 1) / opt.max_frontier_cells
                            : 1;
  Marker fr = base(header, "frontiers", Marker::CUBE_LIST, res);
  size_t k = 0;
  for (const auto& [id, c] : fc.clusters()) {
    const std_msgs::ColorRGBA col = palette(id);
    for (const VoxelKey& cell : c.cells)
      if (k++ % stride == 0) {
        fr.points.push_back(toPointMsg(voxelCenter(cell, res)));
        fr.colors.push_back(col);
      }
  }
  if (!fr.points.empty()) out.markers.push_back(fr);
  return out;
}

}  // namespace efs::planner
