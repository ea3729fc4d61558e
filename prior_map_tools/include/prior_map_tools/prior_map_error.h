// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#pragma once

#include <stdexcept>
#include <string>

namespace efs::prior_map {

/// A sketch or bundle that cannot be used. The message names the file (where there is one) and
/// what is wrong with it, in one line, so a tool can print it and exit non-zero.
class PriorMapError : public std::runtime_error {
 public:
  explicit PriorMapError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace efs::prior_map
