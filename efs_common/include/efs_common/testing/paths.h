// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Where tests find the shared real data (../shared/data, never copied into the repository) and
// where they may write artefacts. Header-only: the defaults are compiled into each test binary
// by efs_gtest(); the environment overrides them.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#ifndef EFS_DEFAULT_SHARED_DATA_DIR
#define EFS_DEFAULT_SHARED_DATA_DIR "../shared/data"
#endif
#ifndef EFS_DEFAULT_TEST_OUTPUT_DIR
#define EFS_DEFAULT_TEST_OUTPUT_DIR "/tmp/efs_test_output"
#endif

namespace efs::testing {

inline std::string sharedDataDir() {
  const char* env = std::getenv("EFS_SHARED_DATA_DIR");
  return env && *env ? std::string(env) : std::string(EFS_DEFAULT_SHARED_DATA_DIR);
}

inline std::string sharedDataPath(const std::string& relative) {
  return sharedDataDir() + "/" + relative;
}

/// A folder for test artefacts (created on demand).
inline std::string testOutputDir() {
  const char* env = std::getenv("EFS_TEST_OUTPUT_DIR");
  const std::string dir = env && *env ? std::string(env) : std::string(EFS_DEFAULT_TEST_OUTPUT_DIR);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace efs::testing
