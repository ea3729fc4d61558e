// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/livox_scan_pattern.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "efs_common/config_check.h"

namespace efs::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

double elevation(const Eigen::Vector3f& d) { return std::asin(std::clamp(d.z(), -1.0f, 1.0f)); }
double azimuth(const Eigen::Vector3f& d) { return std::atan2(d.y(), d.x()); }

TEST(LivoxScanPattern, Mid360DirectionsAreUnitAndInsideTheElevationBand) {
  const LivoxScanPattern p(LivoxPatternConfig::mid360());
  EXPECT_EQ(p.tableSize(), 200000u);
  std::vector<Eigen::Vector3f> dirs;
  p.directions(0, 400000, Eigen::Matrix3f::Identity(), &dirs);
  ASSERT_EQ(dirs.size(), 400000u);
  double el_min = 1e9, el_max = -1e9;
  for (const auto& d : dirs) {
    ASSERT_NEAR(d.norm(), 1.0f, 1e-5f);
    el_min = std::min(el_min, elevation(d));
    el_max = std::max(el_max, elevation(d));
  }
  EXPECT_GE(el_min, -7.0 * kDeg - 1e-4);
  EXPECT_LE(el_max, 52.0 * kDeg + 1e-4);
  EXPECT_LT(el_min, -6.9 * kDeg);  // the band is used to its edges
  EXPECT_GT(el_max, 51.9 * kDeg);
}

// After 1 s every 5 x 5 deg cell of the field of view holds points, and per unit solid angle the
// density is even: each cell's count is within 10% of its solid-angle share.
TEST(LivoxScanPattern, Mid360CoversTheFieldOfViewUniformlyInOneSecond) {
  const LivoxScanPattern p(LivoxPatternConfig::mid360());
  const uint64_t n = p.firstPointAtOrAfter(1.0);
  EXPECT_EQ(n, 200000u);  // point rate
  const int n_az = 72;
  const double el0 = -7.0 * kDeg, el1 = 52.0 * kDeg;
  const int n_el = 12;  // 59 deg / 12 ~ 4.9 deg
  std::vector<int> count(n_az * n_el, 0);
  for (uint64_t k = 0; k < n; ++k) {
    const Eigen::Vector3f d = p.direction(k);
    const int ia = std::min(n_az - 1, static_cast<int>((azimuth(d) + M_PI) / (2 * M_PI) * n_az));
    const int ie =
        std::clamp(static_cast<int>((elevation(d) - el0) / (el1 - el0) * n_el), 0, n_el - 1);
    ++count[ie * n_az + ia];
  }
  const double total_solid = 2 * M_PI * (std::sin(el1) - std::sin(el0));
  for (int ie = 0; ie < n_el; ++ie) {
    const double a = el0 + (el1 - el0) * ie / n_el, b = el0 + (el1 - el0) * (ie + 1) / n_el;
    const double expected = n * (2 * M_PI / n_az) * (std::sin(b) - std::sin(a)) / total_solid;
    for (int ia = 0; ia < n_az; ++ia) {
      EXPECT_NEAR(count[ie * n_az + ia], expected, 0.1 * expected)
          << "cell el " << ie << " az " << ia;
    }
  }
}

// Each 10 Hz frame alone already spans the whole band (every 10 x 10 deg cell hit), and frames
// differ from each other (non-repetitive), also across the table period.
TEST(LivoxScanPattern, Mid360FramesSpanTheFieldOfViewAndNeverRepeat) {
  const LivoxScanPattern p(LivoxPatternConfig::mid360());
  for (int frame = 0; frame < 12; ++frame) {
    const uint64_t k0 = p.firstPointAtOrAfter(0.1 * frame),
                   k1 = p.firstPointAtOrAfter(0.1 * (frame + 1));
    EXPECT_EQ(k1 - k0, 20000u);
    std::vector<int> hit(36 * 6, 0);
    for (uint64_t k = k0; k < k1; ++k) {
      const Eigen::Vector3f d = p.direction(k);
      const int ia = std::min(35, static_cast<int>((azimuth(d) + M_PI) / (2 * M_PI) * 36));
      const int ie =
          std::clamp(static_cast<int>((elevation(d) + 7 * kDeg) / (59 * kDeg) * 6), 0, 5);
      hit[ie * 36 + ia] = 1;
    }
    EXPECT_EQ(std::count(hit.begin(), hit.end(), 1), 36 * 6) << "frame " << frame;
  }
  // Point k and the point one frame / one table period later do not coincide.
  for (uint64_t k : {0ull, 12345ull, 199999ull}) {
    EXPECT_GT((p.direction(k) - p.direction(k + 20000)).norm(), 1e-3f);
    EXPECT_GT((p.direction(k) - p.direction(k + 200000)).norm(), 1e-3f);
  }
}

TEST(LivoxScanPattern, DirectionsBatchMatchesSinglePointsAndIsDeterministic) {
  const LivoxScanPattern a(LivoxPatternConfig::mid360()), b(LivoxPatternConfig::mid360());
  const Eigen::Matrix3f R =
      Eigen::AngleAxisf(0.3f, Eigen::Vector3f(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<Eigen::Vector3f> batch;
  a.directions(199990, 200010, R, &batch);  // straddles a table period
  ASSERT_EQ(batch.size(), 20u);
  for (uint64_t i = 0; i < 20; ++i) {
    EXPECT_LT((batch[i] - R * b.direction(199990 + i)).norm(), 1e-5f);
  }
}

TEST(LivoxScanPattern, AviaStaysInsideItsRosetteFieldOfViewAndFillsIt) {
  const LivoxPatternConfig cfg = LivoxPatternConfig::avia();
  const LivoxScanPattern p(cfg);
  const double h = 0.5 * cfg.avia_fov_horizontal_rad, v = 0.5 * cfg.avia_fov_vertical_rad;
  const int nb = 10;
  std::vector<int> hit(nb * nb, 0);
  const uint64_t n = p.firstPointAtOrAfter(1.0);
  EXPECT_EQ(n, 240000u);
  for (uint64_t k = 0; k < n; ++k) {
    const Eigen::Vector3f d = p.direction(k);
    ASSERT_GT(d.x(), 0.0f);  // forward looking
    const double az = azimuth(d), el = elevation(d);
    // Inside the ellipse (az/h)^2 + (el/v)^2 <= 1.
    ASSERT_LE((az / h) * (az / h) + (el / v) * (el / v), 1.0 + 1e-4);
    const int ia = std::clamp(static_cast<int>((az / h + 1) / 2 * nb), 0, nb - 1);
    const int ie = std::clamp(static_cast<int>((el / v + 1) / 2 * nb), 0, nb - 1);
    hit[ie * nb + ia] = 1;
  }
  // Every grid cell whose centre lies well inside the ellipse is visited.
  for (int ie = 0; ie < nb; ++ie) {
    for (int ia = 0; ia < nb; ++ia) {
      const double x = -1 + (ia + 0.5) * 2.0 / nb, y = -1 + (ie + 0.5) * 2.0 / nb;
      if (x * x + y * y < 0.8) {
        EXPECT_EQ(hit[ie * nb + ia], 1) << ia << "," << ie;
      }
    }
  }
}

TEST(LivoxScanPattern, BadConfigNamesTheKey) {
  LivoxPatternConfig c;
  c.elevation_max_rad = c.elevation_min_rad - 0.1;
  try {
    LivoxScanPattern p(c);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("elevation_max_rad"), std::string::npos);
  }
  c = LivoxPatternConfig();
  c.point_rate_hz = NAN;
  EXPECT_THROW(LivoxScanPattern{c}, ConfigError);
}

}  // namespace
}  // namespace efs::sim
