#include "apps/cli_args.hpp"

#include <sstream>

#include <charconv>
#include <cstdio>
#include <stdexcept>

namespace statebench::app {

CliArgs::CliArgs(const std::vector<std::string>& args, const std::set<std::string>& flags,
                 const std::set<std::string>& options) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.rfind("--", 0) != 0 || a == "--") {
      positional_.push_back(a);
      continue;
    }
    std::string name = a.substr(2);
    std::optional<std::string> inline_value;
    if (const auto eq = name.find('='); eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    if (flags.count(name)) {
      if (inline_value) throw std::invalid_argument("option --" + name + " takes no value");
      flags_.insert(name);
    } else if (options.count(name)) {
      if (inline_value) {
        options_[name] = *inline_value;
      } else if (i + 1 < args.size()) {
        options_[name] = args[++i];
      } else {
        throw std::invalid_argument("option --" + name + " needs a value");
      }
    } else {
      throw std::invalid_argument("unknown option --" + name);
    }
  }
}

std::optional<std::string> CliArgs::Option(const std::string& name) const {
  const auto it = options_.find(name);
  if (it == options_.end()) return std::nullopt;
  return it->second;
}

std::optional<double> CliArgs::Double(const std::string& name) const {
  const auto v = Option(name);
  if (!v) return std::nullopt;
  double out = 0.0;
  const auto [ptr, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
  if (ec != std::errc() || ptr != v->data() + v->size() || v->empty()) {
    throw std::invalid_argument("--" + name + ": expected a number, got '" + *v + "'");
  }
  return out;
}

std::optional<std::uint64_t> CliArgs::Unsigned(const std::string& name) const {
  const auto v = Option(name);
  if (!v) return std::nullopt;
  std::uint64_t out = 0;
  const auto [ptr, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
  if (ec != std::errc() || ptr != v->data() + v->size() || v->empty()) {
    throw std::invalid_argument("--" + name + ": expected a non-negative integer, got '" + *v +
                                "'");
  }
  return out;
}

std::variant<CliArgs, int> ParseCommand(const CommandSpec& spec,
                                        const std::vector<std::string>& argv) {
  std::set<std::string> flags = spec.flags;
  flags.insert("help");
  try {
    CliArgs args(argv, flags, spec.options);
    if (args.Flag("help")) {
      std::printf("%s", spec.usage.c_str());
      return 0;
    }
    if (args.positional().size() != spec.positional) {
      throw std::invalid_argument("expected " + std::to_string(spec.positional) +
                                  " positional argument(s), got " +
                                  std::to_string(args.positional().size()));
    }
    for (const std::string& r : spec.required) {
      if (!args.Option(r)) throw std::invalid_argument("option --" + r + " is required");
    }
    return args;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "statebench %s: %s\n%s", spec.name.c_str(), e.what(), spec.usage.c_str());
    return 2;
  }
}

std::vector<std::string> SplitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace statebench::app
