// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common_ros/param_reader.h"

#include <ros/param.h>

namespace efs::ros_common {

std::vector<std::string> ParamReader::unknownKeys() const {
  std::vector<std::string> all;
  ros::param::getParamNames(all);
  const std::string ns = nh_.getNamespace() + "/";
  std::vector<std::string> unknown;
  for (const auto& full : all) {
    if (full.compare(0, ns.size(), ns) != 0) continue;
    const std::string key = full.substr(ns.size());
    if (known_.count(key)) continue;
    bool claimed = false;
    for (const auto& p : known_prefixes_) claimed = claimed || key.compare(0, p.size(), p) == 0;
    if (!claimed) unknown.push_back(full);
  }
  return unknown;
}

void ParamReader::rejectUnknown() const {
  const auto unknown = unknownKeys();
  if (unknown.empty()) return;
  std::string list;
  for (const auto& k : unknown) list += (list.empty() ? "" : ", ") + k;
  throw ConfigError("unknown parameter(s): " + list + " (misspelt or not used by this node)");
}

}  // namespace efs::ros_common
