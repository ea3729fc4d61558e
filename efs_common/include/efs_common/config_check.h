// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Validation helpers for the `Config` structs of every module. A bad value throws
// std::invalid_argument whose message names the key and the allowed range, so that a node or
// tool can stop with one clear line (DESIGN: fail fast, naming the key).
#pragma once

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace efs {

class ConfigError : public std::invalid_argument {
 public:
  explicit ConfigError(const std::string& what) : std::invalid_argument(what) {}
};

/// Throws ConfigError unless lo <= value <= hi and value is finite.
template <typename T>
void requireInRange(const std::string& key, T value, T lo, T hi) {
  const bool finite = std::isfinite(static_cast<double>(value));
  if (!finite || value < lo || value > hi) {
    std::ostringstream os;
    os << "parameter '" << key << "' = " << value << " is out of range [" << lo << ", " << hi
       << "]";
    throw ConfigError(os.str());
  }
}

/// Throws ConfigError unless value > 0 and finite.
template <typename T>
void requirePositive(const std::string& key, T value) {
  if (!std::isfinite(static_cast<double>(value)) || !(value > T(0))) {
    std::ostringstream os;
    os << "parameter '" << key << "' = " << value << " must be a finite number > 0";
    throw ConfigError(os.str());
  }
}

/// Throws ConfigError with `why` unless `ok`.
inline void requireThat(bool ok, const std::string& key, const std::string& why) {
  if (!ok) throw ConfigError("parameter '" + key + "': " + why);
}

}  // namespace efs
