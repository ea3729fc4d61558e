// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/resource_usage.h"

#include <fstream>
#include <string>

namespace efs {
namespace {

std::size_t readStatusKb(const std::string& key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, key.size(), key) == 0) {
      return static_cast<std::size_t>(std::stoull(line.substr(key.size() + 1)));
    }
  }
  return 0;
}

}  // namespace

std::size_t peakRssBytes() { return readStatusKb("VmHWM") * 1024; }
std::size_t currentRssBytes() { return readStatusKb("VmRSS") * 1024; }

bool resetPeakRss() {
  std::ofstream out("/proc/self/clear_refs");
  if (!out) return false;
  out << "5";
  return static_cast<bool>(out);
}

}  // namespace efs
