// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "prior_map_tools/prior_bundle.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "efs_common/testing/paths.h"
#include "prior_map_tools/prior_map_builder.h"
#include "prior_map_tools/prior_map_error.h"
#include "test_sketches.h"

namespace efs::prior_map {
namespace {

std::string tmpPath(const std::string& name) {
  return efs::testing::testOutputDir() + "/pmt_" + name;
}

PriorBundle sampleBundle() {
  SketchLoadConfig lc;
  lc.scale_guess_m_per_px = 0.1;
  PriorMapConfig config;
  config.guidepoints.mapping_range_m = 3.0;
  return buildPriorBundle(sketchFromImage(test::drawBuilding(), lc, "building.png"), config);
}

std::string readAll(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void writeAll(const std::string& p, const std::string& data) {
  std::ofstream(p, std::ios::binary | std::ios::trunc)
      .write(data.data(), static_cast<std::streamsize>(data.size()));
}

void expectLoadError(const std::string& path, const std::string& needle) {
  try {
    loadPriorBundle(path);
    FAIL() << "expected PriorMapError with '" << needle << "'";
  } catch (const PriorMapError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(PriorBundle, WrittenAndReadBackIsIdentical) {
  const PriorBundle b = sampleBundle();
  const std::string p = tmpPath("roundtrip.prior");
  savePriorBundle(b, p);
  const PriorBundle r = loadPriorBundle(p);
  EXPECT_TRUE(r == b);
  EXPECT_EQ(r.guidepoints.size(), b.guidepoints.size());
  EXPECT_EQ(r.prm.edges.size(), b.prm.edges.size());
  EXPECT_EQ(r.wallPoints().size(), static_cast<size_t>(cv::countNonZero(b.wall_mask)));
}

TEST(PriorBundle, UnreachablePairsSurviveTheRoundTrip) {
  PriorBundle b = sampleBundle();
  ASSERT_GE(b.distances.size(), 2);
  b.distances.set(0, 1, DistanceMatrix::kUnreachable);
  b.distances.set(1, 0, DistanceMatrix::kUnreachable);
  const std::string p = tmpPath("unreachable.prior");
  savePriorBundle(b, p);
  EXPECT_FALSE(loadPriorBundle(p).distances.reachable(0, 1));
}

TEST(PriorBundle, WrongVersionIsRefused) {
  const std::string p = tmpPath("version.prior");
  savePriorBundle(sampleBundle(), p);
  std::string data = readAll(p);
  data[8] = static_cast<char>(PriorBundle::kFormatVersion + 1);
  writeAll(p, data);
  expectLoadError(p, "version");
}

TEST(PriorBundle, TruncatedFileIsRefusedAtEveryLength) {
  const std::string p = tmpPath("full.prior"), t = tmpPath("truncated.prior");
  savePriorBundle(sampleBundle(), p);
  const std::string data = readAll(p);
  for (size_t len : {size_t{0}, size_t{5}, size_t{16}, size_t{30}, data.size() / 3, data.size() / 2,
                     data.size() - 1}) {
    writeAll(t, data.substr(0, len));
    SCOPED_TRACE(len);
    EXPECT_THROW(loadPriorBundle(t), PriorMapError);
  }
  writeAll(t, data.substr(0, data.size() / 2));
  expectLoadError(t, "truncated");
}

TEST(PriorBundle, CorruptByteIsDetected) {
  const std::string p = tmpPath("corrupt.prior");
  savePriorBundle(sampleBundle(), p);
  std::string data = readAll(p);
  data[data.size() / 2] = static_cast<char>(data[data.size() / 2] ^ 0x5a);
  writeAll(p, data);
  expectLoadError(p, "corrupt");
}

TEST(PriorBundle, OtherFilesAreNotBundles) {
  const std::string p = tmpPath("other.prior");
  writeAll(p, "# a YAML file\nresolution: 0.1\n");
  expectLoadError(p, "not a prior bundle");
  expectLoadError(tmpPath("missing.prior"), "cannot open");
}

}  // namespace
}  // namespace efs::prior_map
