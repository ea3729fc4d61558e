// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/segment_distance.h"

#include <gtest/gtest.h>

namespace efs {
namespace {

TEST(SegmentDistance, InteriorEndsAndDegenerateSegments) {
  const Eigen::Vector3d a(0, 0, 0), b(4, 0, 0);
  EXPECT_DOUBLE_EQ(distanceToSegment<3>(Eigen::Vector3d(2, 3, 4), a, b), 5.0);   // beside it
  EXPECT_DOUBLE_EQ(distanceToSegment<3>(Eigen::Vector3d(-3, 4, 0), a, b), 5.0);  // before a
  EXPECT_DOUBLE_EQ(distanceToSegment<3>(Eigen::Vector3d(7, 0, 4), a, b), 5.0);   // past b
  EXPECT_DOUBLE_EQ(distanceToSegment<3>(Eigen::Vector3d(1, 0, 0), a, b), 0.0);   // on it
  EXPECT_DOUBLE_EQ(distanceToSegment<3>(Eigen::Vector3d(3, 4, 0), a, a), 5.0);   // a point
  EXPECT_DOUBLE_EQ(
      distanceToSegment<2>(Eigen::Vector2d(1, 1), Eigen::Vector2d(0, 0), Eigen::Vector2d(2, 2)),
      0.0);
}

}  // namespace
}  // namespace efs
