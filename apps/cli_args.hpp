// Minimal command-line parsing for the statebench subcommands: positional arguments and
// --flag / --key value options, with clear errors for unknown or incomplete options.
#pragma once

#include <map>
#include <optional>
#include <cstdint>
#include <set>
#include <string>
#include <variant>
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
  // Typed options; throw std::invalid_argument "--name: expected ..., got '...'".
  std::optional<double> Double(const std::string& name) const;
  std::optional<std::uint64_t> Unsigned(const std::string& name) const;

 private:
  std::vector<std::string> positional_;
  std::set<std::string> flags_;
  std::map<std::string, std::string> options_;
};

// "a,b,,c" -> {"a", "b", "c"}: the items of a comma-separated option value.
std::vector<std::string> SplitList(const std::string& s);

// What a subcommand accepts.
struct CommandSpec {
  std::string name;   // "simulate"
  std::string usage;  // printed on --help and on bad usage
  std::set<std::string> flags;
  std::set<std::string> options;
  std::size_t positional = 1;           // exact number of positional arguments
  std::vector<std::string> required;    // options that must be given
};

// Parses a subcommand's arguments (--help is always accepted). Returns the arguments, or the
// exit code to stop with: 0 after printing the usage for --help, 2 after printing the problem
// and the usage to stderr.
std::variant<CliArgs, int> ParseCommand(const CommandSpec& spec,
                                        const std::vector<std::string>& argv);

}  // namespace statebench::app
