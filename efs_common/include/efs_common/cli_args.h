// Copyright (c) 2026, explore_from_sketch authors. BSD-3-Clause.
//
// Minimal "--key value" / "--flag" command-line parsing for the suite's tools, with errors that
// name the option. Unknown options are an error, so a typo never silently falls back to a default.
#pragma once

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace efs {

class CliError : public std::invalid_argument {
 public:
  explicit CliError(const std::string& what) : std::invalid_argument(what) {}
};

class CliArgs {
 public:
  /// `valued` lists options that take a value, `flags` those that do not (without "--").
  CliArgs(int argc, const char* const* argv, const std::set<std::string>& valued,
          const std::set<std::string>& flags = {});

  bool has(const std::string& key) const { return values_.count(key) || flags_.count(key); }
  std::string str(const std::string& key, const std::string& fallback) const;
  std::string required(const std::string& key) const;
  double number(const std::string& key, double fallback) const;
  double requiredNumber(const std::string& key) const;
  long integer(const std::string& key, long fallback) const;
  bool flag(const std::string& key) const { return flags_.count(key) > 0; }
  const std::vector<std::string>& positional() const { return positional_; }

 private:
  double parseNumber(const std::string& key, const std::string& text) const;
  std::map<std::string, std::string> values_;
  std::set<std::string> flags_;
  std::vector<std::string> positional_;
};

}  // namespace efs
