// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Plain types shared by the registration core. The sketch ("prior") lives in its own metric
// frame; the observation lives in the world (LIO) frame; efs::Sim2 maps sketch -> world.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace efs::registration {

using Points2d = std::vector<Eigen::Vector2d>;
using Points3d = std::vector<Eigen::Vector3d>;

}  // namespace efs::registration
