// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Trajectory server content <-> messages. PolynomialTrajectory convention used here (the field
// layout of quadrotor_msgs, whose coefficient convention varies between stacks): per segment
// `order[i] + 1` coefficients in coef_x / coef_y / coef_z, ascending powers of the segment's
// local time in seconds (c0 + c1 t + ...), mag_coeff = 1, time[i] = segment duration [s];
// header.stamp is the trajectory's start time. Yaw is carried only as start_yaw / final_yaw
// (the PositionCommand stream carries the full yaw profile).
#pragma once

#include <explore_from_sketch/PolynomialTrajectory.h>
#include <explore_from_sketch/PositionCommand.h>
#include <visualization_msgs/MarkerArray.h>

#include <optional>
#include <string>

#include "minco_traj/local_planner.h"
#include "minco_traj/trajectory.h"
#include "minco_traj/trajectory_server.h"

namespace efs::traj {

explore_from_sketch::PolynomialTrajectory toPolynomialTrajectory(const Trajectory& traj,
                                                                 uint32_t trajectory_id,
                                                                 const std_msgs::Header& header,
                                                                 const std::string& debug_info);
/// Position part of a PolynomialTrajectory written by toPolynomialTrajectory (constant yaw =
/// start_yaw). Empty with a reason in *why if the message is inconsistent.
std::optional<Trajectory> fromPolynomialTrajectory(
    const explore_from_sketch::PolynomialTrajectory& msg, std::string* why);

explore_from_sketch::PositionCommand toPositionCommand(const ReferenceSample& s,
                                                       uint32_t trajectory_id, uint8_t flag,
                                                       const std_msgs::Header& header);

/// Trajectory (line strip sampled every sample_dt_s), corridor polytopes (line lists) and the
/// front-end path (line strip) of one plan. Each call replaces the previous markers.
visualization_msgs::MarkerArray planMarkers(const PlanResult& plan, const Trajectory& traj,
                                            const std_msgs::Header& header, double sample_dt_s);

}  // namespace efs::traj
