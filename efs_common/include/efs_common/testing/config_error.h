// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// The check every module's config test makes: a bad value is refused with an efs::ConfigError
// whose message names the key. Header-only, for gtest binaries.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "efs_common/config_check.h"

namespace efs::testing {

/// Expects `make()` to throw efs::ConfigError naming `key`.
template <typename Make>
void expectConfigErrorNaming(Make&& make, const std::string& key) {
  try {
    make();
    ADD_FAILURE() << "no ConfigError for " << key;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

}  // namespace efs::testing
