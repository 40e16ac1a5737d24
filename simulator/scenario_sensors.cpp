#include "simulator/scenario_sensors.hpp"

#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/error.hpp"
#include "simulator/scenario_faults.hpp"

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> CandidateDirs(const fs::path& scenario_dir) {
  std::vector<fs::path> dirs = {scenario_dir};
  for (fs::path dir = fs::absolute(scenario_dir); !dir.empty(); dir = dir.parent_path()) {
    dirs.push_back(dir / "setups");
    dirs.push_back(dir / "scenarios" / "setups");
    if (dir == dir.parent_path()) break;
  }
  if (const char* source_dir = std::getenv("STATEBENCH_SOURCE_DIR")) {
    dirs.push_back(fs::path(source_dir) / "scenarios" / "setups");
  }
  std::error_code ec;
  const fs::path cwd = fs::current_path(ec);
  if (!ec) dirs.push_back(cwd / "scenarios" / "setups");
  return dirs;
}

std::string ReadText(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw InputError(file.string() + ": cannot read");
  return text.str();
}

}  // namespace

std::optional<fs::path> FindSensorSetupFile(const fs::path& scenario_file,
                                            const std::string& name) {
  if (name.empty()) return std::nullopt;
  const fs::path scenario_dir =
      scenario_file.parent_path().empty() ? fs::path(".") : scenario_file.parent_path();
  fs::path file(name);
  if (!file.has_extension()) file += ".yaml";
  std::vector<fs::path> candidates;
  if (file.is_absolute()) {
    candidates.push_back(file);
  } else {
    for (const fs::path& dir : CandidateDirs(scenario_dir)) candidates.push_back(dir / file);
  }
  std::error_code ec;
  for (const fs::path& candidate : candidates) {
    if (!fs::is_regular_file(candidate, ec)) continue;
    if (fs::exists(scenario_file, ec) && fs::equivalent(candidate, scenario_file, ec)) continue;
    return fs::absolute(candidate).lexically_normal();
  }
  return std::nullopt;
}

ScenarioSensors LoadScenarioSensors(const Scenario& scenario) {
  if (!scenario.sensors) {
    throw InputError(scenario.file.string() +
                     ": field 'sensors': the scenario names no sensor setup (give a setup file, "
                     "e.g. 'sensors: setup2_quadricycle.yaml', see docs/scenarios.md)");
  }
  const YamlNode& node = *scenario.sensors;
  ScenarioSensors out;
  if (node.IsScalar()) {
    const std::string name = node.As<std::string>();
    const auto file = FindSensorSetupFile(scenario.file, name);
    if (!file) {
      node.Fail("unknown sensor setup '" + name +
                "': no such file next to the scenario or in scenarios/setups/");
    }
    out.setup = sensors::LoadSensorSetup(*file);
    out.setup_yaml = ReadText(*file);
  } else {
    node.ExpectMap();
    out.setup = sensors::ParseSensorSetup(node);
    out.setup_yaml = YAML::Dump(node.raw()) + "\n";
  }
  if (scenario.faults) out.faults = ApplyFaults(*scenario.faults, &out.setup);
  if (scenario.mismatch) {
    out.mismatch = ApplyMismatch(*scenario.mismatch, scenario.seed, &out.setup, &out.faults);
  }
  return out;
}

}  // namespace statebench::sim
