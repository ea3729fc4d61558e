// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/simulation_session.h"

#include <algorithm>
#include <string>
#include <utility>

#include "efs_common/config_check.h"
#include "efs_common/resource_usage.h"
#include "marsim_worlds/coverage.h"
#include "marsim_worlds/free_space_component.h"

namespace efs::sim {

void SimulationSessionConfig::validate() const {
  world.validate();
  requireInRange("start_index", start_index, 0, 1000);
  requireInRange("coverage_sample_spacing_m", coverage_sample_spacing_m, 0.5, 100.0);
  sim.validate();
}

SimulationSession::SimulationSession(const SimulationSessionConfig& config)
    : SimulationSession(config, (config.validate(), loadWorld(config.world))) {}

SimulationSession::SimulationSession(const SimulationSessionConfig& config, VoxelWorld world)
    : config_(config), world_(std::move(world)) {
  config_.validate();
  if (config_.start_index >= static_cast<int>(world_.start_poses.size())) {
    throw ConfigError("parameter 'start_index' = " + std::to_string(config_.start_index) +
                      ", but the world has " + std::to_string(world_.start_poses.size()) +
                      " start pose(s)");
  }
  config_.sim.initial_position_m = start().position_m;
  config_.sim.initial_yaw_rad = start().yaw_rad;
  sim_ = std::make_unique<Simulator>(world_, config_.sim);
  if (config_.coverage_enabled) {
    const Stopwatch watch;
    ObservableSurfaceConfig oc;
    oc.voxel_size_m = config_.sim.coverage.voxel_size_m;
    oc.max_range_m = config_.sim.coverage.coverage_range_m;
    auto samples = freeSamplePoints(world_, world_.bounds(), config_.coverage_sample_spacing_m,
                                    config_.sim.vehicle_radius_m);
    coverage_samples_total_ = samples.size();
    const FreeSpaceComponent reachable(world_, start().position_m);
    samples.erase(std::remove_if(samples.begin(), samples.end(),
                                 [&](const Eigen::Vector3d& p) { return !reachable.contains(p); }),
                  samples.end());
    // A world smaller than the sample spacing is still measured, from where the flight starts.
    if (samples.empty()) samples.push_back(start().position_m);
    coverage_samples_reachable_ = samples.size();
    sim_->setCoverageGroundTruth(observableSurfaceKeys(world_, samples, oc));
    ground_truth_s_ = watch.elapsedSeconds();
  }
}

}  // namespace efs::sim
