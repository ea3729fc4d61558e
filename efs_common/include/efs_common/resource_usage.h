// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Wall-clock and memory measurement for tools and benchmarks only. Core algorithms never read a
// clock (time is injected); they are measured from the outside with these.
#pragma once

#include <chrono>
#include <cstddef>

namespace efs {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  void restart() { start_ = std::chrono::steady_clock::now(); }
  double elapsedSeconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  double elapsedMs() const { return 1e3 * elapsedSeconds(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

/// Peak resident set size of this process so far, in bytes (Linux: VmHWM).
std::size_t peakRssBytes();
/// Current resident set size in bytes (Linux: VmRSS).
std::size_t currentRssBytes();
/// Resets the peak RSS counter (Linux >= 4.0 via /proc/self/clear_refs); returns false if not
/// supported, in which case peakRssBytes() keeps reporting the process-wide peak.
bool resetPeakRss();

}  // namespace efs
