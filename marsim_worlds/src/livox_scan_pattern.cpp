// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "marsim_worlds/livox_scan_pattern.h"

#include <algorithm>
#include <cmath>

#include "efs_common/config_check.h"

namespace efs::sim {
namespace {

// R2 sequence constants: 1/g and 1/g^2 for the plastic number g (Roberts 2018). The pair with 1
// is badly approximable, which is what makes every window of the sequence low-discrepancy.
constexpr double kPlastic = 1.32471795724474602596;
constexpr double kR2a = 1.0 / kPlastic;
constexpr double kR2b = 1.0 / (kPlastic * kPlastic);
// The golden angle: successive table periods are turned by it so that they never line up.
const double kGoldenAngle = M_PI * (3.0 - std::sqrt(5.0));
constexpr int kAviaLasers = 6;

double frac(double x) { return x - std::floor(x); }

Eigen::Vector3f fromAzEl(double az, double el) {
  return Eigen::Vector3f(static_cast<float>(std::cos(el) * std::cos(az)),
                         static_cast<float>(std::cos(el) * std::sin(az)),
                         static_cast<float>(std::sin(el)));
}

}  // namespace

void LivoxPatternConfig::validate() const {
  requireInRange("point_rate_hz", point_rate_hz, 1e3, 2e6);
  requireInRange("elevation_min_rad", elevation_min_rad, -M_PI / 2, M_PI / 2);
  requireInRange("elevation_max_rad", elevation_max_rad, -M_PI / 2, M_PI / 2);
  requireThat(elevation_max_rad > elevation_min_rad, "elevation_max_rad",
              "must be greater than elevation_min_rad");
  requireInRange("avia_fov_horizontal_rad", avia_fov_horizontal_rad, 1e-3, M_PI * 0.99);
  requireInRange("avia_fov_vertical_rad", avia_fov_vertical_rad, 1e-3, M_PI * 0.99);
  requireInRange("table_period_s", table_period_s, 0.01, 10.0);
  requireInRange("sweep_block_points", sweep_block_points, 1, 100000);
  requireThat(point_rate_hz * table_period_s >= kAviaLasers, "table_period_s",
              "the table must hold at least a few points");
}

LivoxPatternConfig LivoxPatternConfig::mid360() { return LivoxPatternConfig(); }

LivoxPatternConfig LivoxPatternConfig::avia() {
  LivoxPatternConfig c;
  c.model = LivoxModel::kAvia;
  c.point_rate_hz = 240000.0;
  return c;
}

LivoxScanPattern::LivoxScanPattern(const LivoxPatternConfig& config) : config_(config) {
  config_.validate();
  const auto n =
      static_cast<std::size_t>(std::llround(config_.point_rate_hz * config_.table_period_s));
  table_.resize(n);
  if (config_.model == LivoxModel::kMid360) {
    // Uniform in azimuth and in sin(elevation) = uniform per solid angle over the band.
    const double s0 = std::sin(config_.elevation_min_rad);
    const double s1 = std::sin(config_.elevation_max_rad);
    for (std::size_t k = 0; k < n; ++k) {
      const double az = 2.0 * M_PI * frac(0.5 + kR2a * static_cast<double>(k));
      const double s = s0 + (s1 - s0) * frac(0.5 + kR2b * static_cast<double>(k));
      table_[k] = fromAzEl(az, std::asin(s));
    }
    // Fire each block in azimuth order, as a spinning head sweeps: the block's set of directions
    // (and so every window of whole blocks) is unchanged, but consecutive rays are neighbours,
    // which keeps a world's ray caster in cache.
    const std::size_t b = static_cast<std::size_t>(config_.sweep_block_points);
    for (std::size_t k0 = 0; b > 1 && k0 < n; k0 += b) {
      std::sort(table_.begin() + k0, table_.begin() + std::min(n, k0 + b),
                [](const Eigen::Vector3f& a, const Eigen::Vector3f& c) {
                  return std::atan2(a.y(), a.x()) < std::atan2(c.y(), c.x());
                });
    }
    rotate_per_period_ = true;
  } else {
    // Two counter-rotating prisms: the beam deflection is the sum of two unit phasors, which
    // draws a rosette filling the unit disk; an irrational speed ratio keeps it from closing.
    const double f1_hz = 191.0;
    const double f2_hz = f1_hz * (std::sqrt(5.0) - 1.0) / 2.0;
    const double per_laser_rate = config_.point_rate_hz / kAviaLasers;
    for (std::size_t k = 0; k < n; ++k) {
      const int laser = static_cast<int>(k % kAviaLasers);
      const double t = static_cast<double>(k / kAviaLasers) / per_laser_rate;
      const double ph1 = 2.0 * M_PI * (f1_hz * t + laser / double(kAviaLasers));
      const double ph2 = -2.0 * M_PI * (f2_hz * t + laser * kR2a);
      const double x = 0.5 * (std::cos(ph1) + std::cos(ph2));
      const double y = 0.5 * (std::sin(ph1) + std::sin(ph2));
      table_[k] = fromAzEl(0.5 * config_.avia_fov_horizontal_rad * x,
                           0.5 * config_.avia_fov_vertical_rad * y);
    }
    // Turning a forward-looking ellipse about z would move the field of view; it repeats.
    rotate_per_period_ = false;
  }
}

Eigen::Vector3f LivoxScanPattern::direction(uint64_t k) const {
  const uint64_t n = table_.size();
  const Eigen::Vector3f& d = table_[k % n];
  if (!rotate_per_period_) return d;
  const double a = kGoldenAngle * static_cast<double>(k / n);
  const float c = static_cast<float>(std::cos(a)), s = static_cast<float>(std::sin(a));
  return Eigen::Vector3f(c * d.x() - s * d.y(), s * d.x() + c * d.y(), d.z());
}

void LivoxScanPattern::directions(uint64_t k_begin, uint64_t k_end,
                                  const Eigen::Matrix3f& R_out_sensor,
                                  std::vector<Eigen::Vector3f>* dirs_out) const {
  const uint64_t n = table_.size();
  dirs_out->reserve(dirs_out->size() + (k_end > k_begin ? k_end - k_begin : 0));
  uint64_t k = k_begin;
  while (k < k_end) {
    const uint64_t cycle = k / n;
    const uint64_t chunk_end = std::min<uint64_t>(k_end, (cycle + 1) * n);
    Eigen::Matrix3f R = R_out_sensor;
    if (rotate_per_period_) {
      R = R_out_sensor *
          Eigen::AngleAxisf(static_cast<float>(std::fmod(kGoldenAngle * cycle, 2.0 * M_PI)),
                            Eigen::Vector3f::UnitZ())
              .toRotationMatrix();
    }
    for (uint64_t j = k; j < chunk_end; ++j) dirs_out->push_back(R * table_[j - cycle * n]);
    k = chunk_end;
  }
}

uint64_t LivoxScanPattern::firstPointAtOrAfter(double t_s) const {
  if (t_s <= 0.0) return 0;
  // The small tolerance absorbs rounding of t = k / rate so that step boundaries are exact.
  return static_cast<uint64_t>(std::ceil(t_s * config_.point_rate_hz - 1e-6));
}

}  // namespace efs::sim
