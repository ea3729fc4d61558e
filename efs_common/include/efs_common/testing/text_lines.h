// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The lines of a text a test wrote (a CSV log, a report), without their line ends.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace efs::testing {

inline std::vector<std::string> textLines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

}  // namespace efs::testing
