// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Point clouds as PCD files (the format PCL, CloudCompare and rviz tools read): x, y, z of any
// PCD (ascii, binary, binary_compressed; other fields ignored) and binary x/y/z float output.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace efs {

/// x, y, z of every point of a PCD file (points with a non-finite coordinate are dropped).
/// Throws std::runtime_error naming the file, the line or byte count, and what is wrong.
std::vector<Eigen::Vector3f> loadPcdPoints(const std::string& path);

/// Writes `points_m` (non-finite ones skipped) as a binary PCD v0.7 with fields x y z. The file
/// appears whole or not at all (written to `path`.tmp, then renamed). Throws std::runtime_error
/// naming the path when it cannot be written.
void writePcdBinary(const std::string& path, const std::vector<Eigen::Vector3f>& points_m);

}  // namespace efs
