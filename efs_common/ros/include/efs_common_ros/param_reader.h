// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Reads a node's private parameters into a core Config, remembering which keys it asked for, so
// that a misspelt or obsolete key in a YAML file is an error instead of a silently ignored line.
// Every failure throws efs::ConfigError naming the full parameter name.
#pragma once

#include <ros/node_handle.h>

#include <set>
#include <string>
#include <vector>

#include "efs_common/config_check.h"

namespace efs::ros_common {

class ParamReader {
 public:
  /// `nh` is normally the private handle ("~").
  explicit ParamReader(const ros::NodeHandle& nh) : nh_(nh) {}

  /// Reads `key` into `value` if set, keeping the default otherwise; throws if it is set to a
  /// value of the wrong type.
  template <typename T>
  void get(const std::string& key, T& value) {
    known_.insert(key);
    if (!nh_.hasParam(key)) return;
    T read{};
    if (!nh_.getParam(key, read)) {
      throw ConfigError("parameter '" + nh_.resolveName(key) + "' has the wrong type");
    }
    value = read;
  }

  /// Like get(), but the parameter must be set.
  template <typename T>
  void require(const std::string& key, T& value) {
    known_.insert(key);
    if (!nh_.hasParam(key)) {
      throw ConfigError("required parameter '" + nh_.resolveName(key) + "' is not set");
    }
    get(key, value);
  }

  /// Marks a whole sub-namespace as read by someone else (e.g. a nested component).
  void claimNamespace(const std::string& prefix) { known_prefixes_.push_back(prefix); }

  /// Throws if the node's namespace holds parameters nobody read.
  void rejectUnknown() const;

  /// Keys that were set but never read (for tests and messages).
  std::vector<std::string> unknownKeys() const;

 private:
  ros::NodeHandle nh_;
  std::set<std::string> known_;
  std::vector<std::string> known_prefixes_;
};

}  // namespace efs::ros_common
