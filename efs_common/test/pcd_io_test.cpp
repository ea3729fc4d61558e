// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/pcd_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "efs_common/testing/paths.h"

namespace efs {
namespace {

std::string outPath(const std::string& name) { return testing::testOutputDir() + "/" + name; }

TEST(PcdIo, BinaryRoundTripKeepsEveryFinitePointBitExact) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Eigen::Vector3f> in = {
      {1.5f, -2.25f, 3.0f}, {nan, 0.f, 0.f}, {1e6f, -1e-6f, 0.1f}, {0.f, 0.f, 0.f}};
  const std::string path = outPath("pcd_io_roundtrip.pcd");
  writePcdBinary(path, in);
  const std::vector<Eigen::Vector3f> out = loadPcdPoints(path);
  ASSERT_EQ(out.size(), 3u);  // the NaN point is not written
  EXPECT_EQ(out[0], in[0]);
  EXPECT_EQ(out[1], in[2]);
  EXPECT_EQ(out[2], in[3]);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(PcdIo, HeaderIsWhatPclReads) {
  const std::string path = outPath("pcd_io_header.pcd");
  writePcdBinary(path, {{1, 2, 3}, {4, 5, 6}});
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string s = ss.str();
  const std::string header =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\n"
      "TYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\n"
      "DATA binary\n";
  ASSERT_EQ(s.substr(0, header.size()), header);
  EXPECT_EQ(s.size(), header.size() + 2 * 3 * sizeof(float));
}

TEST(PcdIo, EmptyCloudIsAValidFile) {
  const std::string path = outPath("pcd_io_empty.pcd");
  writePcdBinary(path, {});
  EXPECT_TRUE(loadPcdPoints(path).empty());
}

TEST(PcdIo, UnwritablePathIsNamed) {
  const std::string path = "/nonexistent_dir_for_efs/map.pcd";
  try {
    writePcdBinary(path, {{1, 2, 3}});
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace efs
