// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// A world and a simulator flying in it, set up the same way for every caller (the ROS node, the
// in-process mission, the benchmarks): the world loaded or generated, the vehicle placed at one
// of the world's start poses, and the ground-truth observable surface computed for coverage
// (seen from the free space the start can reach).
#pragma once

#include <cstddef>
#include <memory>

#include "marsim_worlds/simulator.h"
#include "marsim_worlds/voxel_world.h"
#include "marsim_worlds/world_source.h"

namespace efs::sim {

struct SimulationSessionConfig {
  WorldSource world;
  int start_index = 0;  ///< which of the world's start poses
  bool coverage_enabled = true;
  double coverage_sample_spacing_m = 3.0;  ///< free-space samples for the observable surface
  /// Its initial pose is replaced by the chosen start pose.
  SimulatorConfig sim;
  /// Throws efs::ConfigError naming the key.
  void validate() const;
};

class SimulationSession {
 public:
  /// Loads the world and builds the simulator. Throws efs::ConfigError for a bad configuration or
  /// a start index the world does not have, std::runtime_error for a world that cannot be loaded.
  explicit SimulationSession(const SimulationSessionConfig& config);
  /// Same, on a world the caller has already loaded (moved in).
  SimulationSession(const SimulationSessionConfig& config, VoxelWorld world);
  SimulationSession(const SimulationSession&) = delete;
  SimulationSession& operator=(const SimulationSession&) = delete;

  const VoxelWorld& world() const { return world_; }
  Simulator& simulator() { return *sim_; }
  const Simulator& simulator() const { return *sim_; }
  const StartPose& start() const { return world_.start_poses[config_.start_index]; }
  /// Time spent computing the ground-truth surface (0 without coverage).
  double groundTruthSeconds() const { return ground_truth_s_; }
  /// Free-space samples the ground-truth surface was seen from, and how many of the free ones
  /// the start could reach (the others, outside a building or in a sealed room, are left out).
  std::size_t coverageSamplesTotal() const { return coverage_samples_total_; }
  std::size_t coverageSamplesReachable() const { return coverage_samples_reachable_; }
  const SimulationSessionConfig& config() const { return config_; }

 private:
  SimulationSessionConfig config_;
  VoxelWorld world_;  // declared before sim_: the simulator refers to it
  std::unique_ptr<Simulator> sim_;
  double ground_truth_s_ = 0.0;
  std::size_t coverage_samples_total_ = 0;
  std::size_t coverage_samples_reachable_ = 0;
};

}  // namespace efs::sim
