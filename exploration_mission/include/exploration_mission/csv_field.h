// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#pragma once

#include <string>

namespace efs::mission {

/// RFC 4180 field: quoted, inner quotes doubled (the logs' messages hold commas).
inline std::string csvQuoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + '"';
}

}  // namespace efs::mission
