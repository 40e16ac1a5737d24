#include "apps/sweep_run_record.hpp"

#include <signal.h>

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <vector>

#include "apps/command_support.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

// The last `lines` non-empty lines of a file, joined by " | ".
std::string Tail(const fs::path& file, std::size_t lines) {
  std::ifstream in(file);
  std::vector<std::string> all;
  std::string line;
  while (std::getline(in, line)) {
    if (const auto cr = line.rfind('\r'); cr != std::string::npos) line = line.substr(cr + 1);
    if (!line.empty()) all.push_back(line);
  }
  std::string tail;
  for (std::size_t i = all.size() > lines ? all.size() - lines : 0; i < all.size(); ++i) {
    tail += (tail.empty() ? "" : " | ") + all[i];
  }
  return tail;
}

std::optional<nlohmann::json> ReadJson(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

}  // namespace

reports::RunRecord RecordOfFinishedRun(const SweepRun& run, const std::string& sweep,
                                       const std::string& code_version, const ChildExit& exit,
                                       const fs::path& dir) {
  reports::RunRecord r;
  r.id = run.id;
  r.sweep = sweep;
  r.scenario = run.scenario;
  r.seed = run.seed;
  r.parameters = run.parameters;
  r.code_version = code_version;
  r.exit_code = exit.exit_code;
  r.wall_s = exit.wall_s;
  r.cpu_s = exit.cpu_s;
  r.run_dir = fs::absolute(dir).string();
  r.artifacts.push_back({"", "scenario", (dir / "scenario.yaml").string()});
  r.artifacts.push_back({"", "stderr", (dir / "stderr.log").string()});

  std::string problem;
  const std::optional<nlohmann::json> summary = ReadJson(dir / "run.json");
  if (exit.signal != 0) {
    problem = std::string("killed by signal ") + std::to_string(exit.signal) + " (" +
              strsignal(exit.signal) + ")";
  } else if (exit.exit_code != 0 && exit.exit_code != kExitNoEstimate) {
    // kExitNoEstimate: the run is complete, an estimator never initialised (its metrics say
    // so: compared 0, counted as unavailable by `results summary`).
    problem = "exit code " + std::to_string(exit.exit_code);
  } else if (!summary) {
    problem = "no readable run.json";
  }
  if (summary) {
    r.artifacts.push_back({"", "run_summary", (dir / "run.json").string()});
    if (summary->contains("cache")) r.cache = (*summary)["cache"];
  }
  if (problem.empty()) {
    for (const std::string& label : run.estimators) {
      const fs::path metrics_file = dir / label / "metrics.json";
      const std::optional<nlohmann::json> metrics = ReadJson(metrics_file);
      if (!metrics) {
        problem = "no readable " + (fs::path(label) / "metrics.json").string();
        break;
      }
      for (const auto& [name, value] : reports::FlattenMetrics(*metrics)) {
        r.metrics.push_back({label, name, value});
      }
      r.artifacts.push_back({label, "metrics", metrics_file.string()});
      r.artifacts.push_back({label, "estimate", (dir / label / "estimate.csv").string()});
      r.artifacts.push_back({label, "diagnostics", (dir / label / "diagnostics.json").string()});
    }
  }
  if (problem.empty()) {
    r.status = "ok";
  } else {
    r.status = "failed";
    r.metrics.clear();
    const std::string tail = Tail(dir / "stderr.log", 3);
    r.error = problem + (tail.empty() ? "" : ": " + tail);
  }
  return r;
}

}  // namespace statebench::app
