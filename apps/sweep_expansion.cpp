#include "apps/sweep_expansion.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>

#include "apps/scenario_estimators.hpp"
#include "core/content_hash.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/random.hpp"
#include "core/yaml_merge.hpp"
#include "simulator/scenario.hpp"
#include "simulator/scenario_resolution.hpp"
#include "simulator/scenario_sensors.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

std::string Text(const YAML::Node& value) {
  if (value.IsScalar()) return value.as<std::string>();
  YAML::Emitter out;
  out << YAML::Flow << value;
  return out.c_str();
}

YAML::Node Draw(const SweepAxis& axis, std::uint64_t seed) {
  std::mt19937_64 rng = MakeRng(seed, "sweep axis " + axis.name);
  double v = 0.0;
  switch (axis.kind) {
    case SweepAxis::Kind::kValues:
      break;
    case SweepAxis::Kind::kChoice: {
      const auto i = static_cast<std::size_t>(Uniform01(rng) * static_cast<double>(axis.values.size()));
      return axis.values[std::min(i, axis.values.size() - 1)];
    }
    case SweepAxis::Kind::kUniform:
      v = axis.a + (axis.b - axis.a) * Uniform01(rng);
      break;
    case SweepAxis::Kind::kNormal: {
      NormalSampler normal;
      v = axis.a + axis.b * normal(rng);
      break;
    }
  }
  std::string text;
  AppendNumber(text, v);
  return YAML::Node(text);
}

// Each combination of the value axes: indices into their values.
std::vector<std::vector<std::size_t>> Combinations(const SweepSpec& spec) {
  std::vector<std::size_t> sizes;
  for (const SweepAxis& axis : spec.axes) sizes.push_back(axis.random() ? 1 : axis.values.size());
  std::vector<std::vector<std::size_t>> combos;
  if (spec.zip) {
    std::size_t n = 1;
    for (const SweepAxis& axis : spec.axes) {
      if (!axis.random()) n = axis.values.size();
    }
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<std::size_t> combo;
      for (const SweepAxis& axis : spec.axes) combo.push_back(axis.random() ? 0 : i);
      combos.push_back(combo);
    }
    return combos;
  }
  std::vector<std::size_t> combo(sizes.size(), 0);
  while (true) {
    combos.push_back(combo);
    std::size_t k = sizes.size();
    while (k > 0) {
      --k;
      if (++combo[k] < sizes[k]) break;
      combo[k] = 0;
      if (k == 0) return combos;
    }
    if (sizes.empty()) return combos;
  }
}

// Keeps the estimators the sweep names (as `statebench run --estimators` picks them) in the
// scenario's order; returns their labels.
std::vector<std::string> SelectEstimators(YAML::Node& resolved, const SweepSpec& spec,
                                          const std::string& scenario_where) {
  const YAML::Node all = resolved["estimators"];
  std::vector<sim::EstimatorSpec> specs;
  for (const YAML::Node& e : all) {
    sim::EstimatorSpec entry;
    entry.label = e["name"].as<std::string>();
    entry.type = e["type"].as<std::string>();
    specs.push_back(entry);
  }
  if (!spec.estimators.empty()) {
    try {
      specs = ChooseEstimators(specs, spec.estimators, "the scenario at " + scenario_where);
    } catch (const std::invalid_argument& e) {
      throw InputError(spec.estimators_where + ": field 'estimators': " + e.what());
    }
  }
  YAML::Node kept(YAML::NodeType::Sequence);
  std::vector<std::string> labels;
  for (const sim::EstimatorSpec& chosen : specs) {
    for (const YAML::Node& e : all) {
      if (e["name"].as<std::string>() == chosen.label) kept.push_back(e);
    }
    labels.push_back(chosen.label);
  }
  resolved["estimators"] = kept;
  return labels;
}

// Checks a run's scenario the way `statebench run` does before it simulates anything.
void CheckRunnable(const std::string& yaml, const fs::path& scratch) {
  const fs::path file = scratch / "scenario.yaml";
  std::ofstream(file) << yaml;
  const sim::Scenario scenario = sim::LoadScenario(file);
  const est::EstimatorSensorSetup setup = EstimatorSetupOf(sim::LoadScenarioSensors(scenario));
  for (const sim::EstimatorSpec& spec : sim::ScenarioEstimators(scenario)) {
    MakeScenarioEstimator(spec, scenario, setup, scratch / spec.label);
  }
}

class ScratchDir {
 public:
  ScratchDir() {
    path_ = fs::temp_directory_path() / ("statebench-sweep-check-" + std::to_string(getpid()));
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string FirstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

}  // namespace

std::vector<SweepRun> ExpandSweep(const SweepSpec& spec, const std::string& code_version,
                                  std::optional<double> duration_override) {
  std::vector<SweepRun> runs;
  std::map<std::string, std::size_t> first_with_id;
  const ScratchDir scratch;
  const std::vector<std::vector<std::size_t>> combos = Combinations(spec);
  for (std::size_t s = 0; s < spec.scenarios.size(); ++s) {
    const YAML::Node base = sim::ResolveScenario(spec.scenarios[s]);
    // Every axis path must exist in the base scenario (the last key may be new to a map; the
    // run check below says whether it is a field).
    for (const SweepAxis& axis : spec.axes) {
      try {
        YAML::Node probe = YAML::Clone(base);
        sim::SetScenarioValue(probe, axis.path, axis.random() ? YAML::Node(0.0) : axis.values.front());
      } catch (const std::invalid_argument& e) {
        throw InputError(axis.where + ": field 'axes." + axis.name + ".path': '" + axis.path +
                         "' does not exist in " + spec.scenarios[s].string() + ": " + e.what());
      }
    }
    for (const std::vector<std::size_t>& combo : combos) {
      for (const std::uint64_t seed : spec.seeds) {
        SweepRun run;
        run.index = runs.size();
        run.scenario_file = spec.scenarios[s];
        run.seed = seed;
        YAML::Node resolved = YAML::Clone(base);
        run.scenario = resolved["name"] ? resolved["name"].as<std::string>() : "";
        resolved["seed"] = seed;
        const std::optional<double> duration = duration_override ? duration_override
                                                                 : spec.duration_s;
        if (duration) resolved["duration_s"] = *duration;
        for (std::size_t a = 0; a < spec.axes.size(); ++a) {
          const SweepAxis& axis = spec.axes[a];
          const YAML::Node value = axis.random() ? Draw(axis, seed) : axis.values[combo[a]];
          sim::SetScenarioValue(resolved, axis.path, value);
          run.parameters.emplace_back(axis.name, Text(value));
        }
        run.estimators = SelectEstimators(resolved, spec, spec.scenario_where[s]);
        run.scenario_yaml = "# Run of sweep '" + spec.name + "' (" + spec.file.string() +
                            "): " + spec.scenarios[s].string() + ", seed " +
                            std::to_string(seed) + "\n" + ToYamlText(resolved);
        try {
          CheckRunnable(run.scenario_yaml, scratch.path());
        } catch (const InputError& e) {
          std::string axes;
          for (const auto& [name, value] : run.parameters) {
            axes += (axes.empty() ? "" : ", ") + name + " = " + value;
          }
          const std::string where = spec.axes.empty() ? spec.scenario_where[s] : spec.axes.front().where;
          throw InputError(where + ": the run with " + (axes.empty() ? "no axis" : axes) +
                           ", seed " + std::to_string(seed) + " is not a valid scenario: " +
                           FirstLine(e.what()));
        }
        YAML::Node simulated = YAML::Clone(resolved);
        simulated.remove("estimators");
        run.simulation_group = Sha256()
                                   .Field("simulation group v1")
                                   .Field(sim::ScenarioFingerprint(simulated))
                                   .Hex();
        run.id = Sha256()
                     .Field("sweep run v1")
                     .Field(code_version)
                     .Field(sim::ScenarioFingerprint(resolved))
                     .Hex()
                     .substr(0, 16);
        if (const auto seen = first_with_id.find(run.id); seen != first_with_id.end()) {
          const SweepRun& other = runs[seen->second];
          std::string axes;
          for (const SweepAxis& axis : spec.axes) axes += (axes.empty() ? "" : ", ") + axis.name;
          throw InputError((spec.axes.empty() ? spec.scenario_where[s] : spec.axes.front().where) +
                           ": runs " + std::to_string(other.index + 1) + " and " +
                           std::to_string(run.index + 1) + " are the same run: an axis (" + axes +
                           ") changes nothing they use, e.g. an option of an estimator the "
                           "sweep does not run");
        }
        first_with_id[run.id] = runs.size();
        runs.push_back(std::move(run));
      }
    }
  }
  return runs;
}

std::vector<SweepRun> ShardOf(const std::vector<SweepRun>& runs, int shard, int shards) {
  std::vector<SweepRun> mine;
  for (const SweepRun& run : runs) {
    if (static_cast<int>(run.index % static_cast<std::size_t>(shards)) == shard - 1) {
      mine.push_back(run);
    }
  }
  return mine;
}

std::string CodeVersion() {
  const char* source = std::getenv("STATEBENCH_SOURCE_DIR");
  const std::string dir = source ? source : ".";
  const auto read = [](const std::string& command) {
    std::string out;
    if (FILE* pipe = popen(command.c_str(), "r")) {
      char buffer[256];
      while (std::fgets(buffer, sizeof(buffer), pipe)) out += buffer;
      if (pclose(pipe) != 0) out.clear();
    }
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    return out;
  };
  const std::string commit = read("git -C '" + dir + "' rev-parse HEAD 2>/dev/null");
  if (commit.empty()) return std::string("statebench ") + STATEBENCH_VERSION;
  const std::string changes =
      read("git -C '" + dir + "' status --porcelain --untracked-files=no 2>/dev/null");
  return commit + (changes.empty() ? "" : "-dirty");
}

}  // namespace statebench::app
