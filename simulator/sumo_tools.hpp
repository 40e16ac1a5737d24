// Locating and running SUMO's command-line tools (netgenerate, netconvert, duarouter) as
// subprocesses. Nothing is printed: each tool's output goes to a log file whose tail is returned.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace statebench::sim {

// A seed for a SUMO tool's --seed option (0 .. 2^31 - 2), derived from a scenario seed and a
// stream name with core/random.hpp.
std::int64_t SumoSeed(std::uint64_t seed, std::string_view stream_name);

// $SUMO_HOME, or /usr/share/sumo (Debian) when unset. Passed on to every tool.
std::string SumoHome();

struct SumoTools {
  std::filesystem::path netgenerate;  // empty: not found
  std::filesystem::path netconvert;
  std::filesystem::path duarouter;

  // Searches $PATH, then $SUMO_HOME/bin.
  static SumoTools Find();
  // Searches a colon-separated directory list only (tests use it to simulate missing tools).
  static SumoTools FindIn(const std::string& search_path);
};

struct ToolRun {
  int exit_code = -1;    // -1: could not start or killed by a signal
  std::string log_tail;  // last lines of the tool's stdout+stderr
};

// Runs `tool args...` with SUMO_HOME set, stdout and stderr into `log_file`; waits for it.
ToolRun RunTool(const std::filesystem::path& tool, const std::vector<std::string>& args,
                const std::filesystem::path& log_file);

}  // namespace statebench::sim
