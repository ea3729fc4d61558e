// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Deterministic randomness for the world and sketch generators. std::*_distribution are
// implementation-defined, so a seed would not give the same world on another standard library;
// these helpers give bit-identical sequences everywhere.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>

namespace efs::sim {

/// SplitMix64 stream (Steele et al. 2014): tiny state, passes BigCrush, fully portable.
class SeededRandom {
 public:
  explicit SeededRandom(uint64_t seed) : state_(seed) {}

  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n).
  uint64_t index(uint64_t n) { return n == 0 ? 0 : next() % n; }
  bool chance(double p) { return uniform() < p; }
  /// Standard normal by Box-Muller (one of the pair is discarded to keep the stream simple).
  double normal() {
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  /// A child stream whose sequence does not overlap this one's in practice.
  SeededRandom fork(uint64_t salt) { return SeededRandom(next() ^ (salt * 0xD1B54A32D192ED03ULL)); }

 private:
  uint64_t state_;
};

/// Smooth lattice value noise in [-1, 1] with fractal octaves; a pure function of (seed, p).
class ValueNoise {
 public:
  explicit ValueNoise(uint64_t seed, double wavelength_m = 4.0, int octaves = 2)
      : seed_(seed), inv_wavelength_(1.0 / wavelength_m), octaves_(octaves) {}

  double operator()(const Eigen::Vector3d& p_m) const {
    double sum = 0.0, amp = 1.0, norm = 0.0, f = inv_wavelength_;
    for (int o = 0; o < octaves_; ++o) {
      sum += amp * lattice(p_m * f, static_cast<uint64_t>(o));
      norm += amp;
      amp *= 0.5;
      f *= 2.0;
    }
    return sum / norm;
  }

  double operator()(double x, double y) const { return (*this)(Eigen::Vector3d(x, y, 0.0)); }

 private:
  double hashValue(int64_t x, int64_t y, int64_t z, uint64_t octave) const {
    uint64_t h = seed_ ^ (octave * 0x9E3779B97F4A7C15ULL);
    h ^= static_cast<uint64_t>(x) * 0xBF58476D1CE4E5B9ULL;
    h = (h ^ (h >> 29)) * 0x94D049BB133111EBULL;
    h ^= static_cast<uint64_t>(y) * 0xD1B54A32D192ED03ULL;
    h = (h ^ (h >> 31)) * 0xBF58476D1CE4E5B9ULL;
    h ^= static_cast<uint64_t>(z) * 0x9E3779B97F4A7C15ULL;
    h = (h ^ (h >> 30)) * 0x94D049BB133111EBULL;
    h ^= h >> 31;
    return static_cast<double>(h >> 11) * (2.0 / 9007199254740992.0) - 1.0;
  }

  double lattice(const Eigen::Vector3d& q, uint64_t octave) const {
    const double fx = std::floor(q.x()), fy = std::floor(q.y()), fz = std::floor(q.z());
    const auto ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy),
               iz = static_cast<int64_t>(fz);
    auto smooth = [](double t) { return t * t * (3.0 - 2.0 * t); };
    const double tx = smooth(q.x() - fx), ty = smooth(q.y() - fy), tz = smooth(q.z() - fz);
    double c[2][2];
    for (int dz = 0; dz < 2; ++dz) {
      for (int dy = 0; dy < 2; ++dy) {
        const double a = hashValue(ix, iy + dy, iz + dz, octave);
        const double b = hashValue(ix + 1, iy + dy, iz + dz, octave);
        c[dz][dy] = a + (b - a) * tx;
      }
    }
    const double y0 = c[0][0] + (c[0][1] - c[0][0]) * ty;
    const double y1 = c[1][0] + (c[1][1] - c[1][0]) * ty;
    return y0 + (y1 - y0) * tz;
  }

  uint64_t seed_;
  double inv_wavelength_;
  int octaves_;
};

}  // namespace efs::sim
