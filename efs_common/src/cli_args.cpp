// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
#include "efs_common/cli_args.h"

#include <cmath>

namespace efs {

CliArgs::CliArgs(int argc, const char* const* argv, const std::set<std::string>& valued,
                 const std::set<std::string>& flags) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0) {
      positional_.push_back(a);
      continue;
    }
    std::string key = a.substr(2), value;
    const auto eq = key.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = key.substr(eq + 1);
      key = key.substr(0, eq);
    }
    if (flags.count(key)) {
      if (inline_value) throw CliError("option --" + key + " takes no value");
      flags_.insert(key);
    } else if (valued.count(key)) {
      if (!inline_value) {
        if (i + 1 >= argc) throw CliError("option --" + key + " needs a value");
        value = argv[++i];
      }
      values_[key] = value;
    } else {
      throw CliError("unknown option --" + key);
    }
  }
}

std::string CliArgs::str(const std::string& key, const std::string& fallback) const {
  const auto it = values_.find(key);
  return it == values_.end() ? fallback : it->second;
}

std::string CliArgs::required(const std::string& key) const {
  const auto it = values_.find(key);
  if (it == values_.end()) throw CliError("missing required option --" + key);
  return it->second;
}

double CliArgs::parseNumber(const std::string& key, const std::string& text) const {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used != text.size()) throw std::invalid_argument(text);
    return v;  // NaN and infinities pass through: the Config's validate() names the parameter.
  } catch (const std::exception&) {
    throw CliError("option --" + key + " expects a number, got '" + text + "'");
  }
}

double CliArgs::number(const std::string& key, double fallback) const {
  const auto it = values_.find(key);
  return it == values_.end() ? fallback : parseNumber(key, it->second);
}

double CliArgs::requiredNumber(const std::string& key) const {
  return parseNumber(key, required(key));
}

long CliArgs::integer(const std::string& key, long fallback) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  const double v = parseNumber(key, it->second);
  if (!std::isfinite(v) || v != std::floor(v)) {
    throw CliError("option --" + key + " expects an integer, got '" + it->second + "'");
  }
  return static_cast<long>(v);
}

}  // namespace efs
