// Minimal command-line parsing for the statebench subcommands: positional arguments and
// --flag / --key value options, with clear errors for unknown or incomplete options.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace statebench::app {

class CliArgs {
 public:
  // `flags` take no value; `options` take one value. Throws std::invalid_argument on unknown
  // options or a missing value.
  CliArgs(const std::vector<std::string>& args, const std::set<std::string>& flags,
          const std::set<std::string>& options);

  const std::vector<std::string>& positional() const { return positional_; }
  bool Flag(const std::string& name) const { return flags_.count(name) > 0; }
  std::optional<std::string> Option(const std::string& name) const;

 private:
  std::vector<std::string> positional_;
  std::set<std::string> flags_;
  std::map<std::string, std::string> options_;
};

}  // namespace statebench::app
