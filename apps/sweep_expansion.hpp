// A sweep file expanded into runs: each a self-contained scenario (scenario_resolution.hpp)
// with the axes' values set, one seed and the chosen estimators, and a deterministic id.
//
// Order: scenarios as listed, then the axes' combinations (grid: the first axis varies slowest;
// zip: the i-th values together), then the seeds; random axes draw one value per run from a
// stream of the run's seed and the axis name, so a run's draw does not depend on the others.
// The id is the first 16 hex digits of SHA-256 over the code version and the run's scenario
// fingerprint (scenario, setup, estimator options, seed, duration, with files by content).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "apps/sweep_file.hpp"

namespace statebench::app {

struct SweepRun {
  std::string id;
  std::size_t index = 0;  // position in the expansion
  std::string scenario;   // the base scenario's name
  std::filesystem::path scenario_file;
  std::uint64_t seed = 0;
  std::vector<std::pair<std::string, std::string>> parameters;  // axis name, value as text
  std::vector<std::string> estimators;                          // labels
  std::string scenario_yaml;  // what `statebench run` runs
  // Equal for runs that differ only in their estimators: they simulate the same (SUMO, sensors,
  // faults, mismatch) and share every cached stage (sweep_schedule.hpp).
  std::string simulation_group;
};

// Throws InputError naming the sweep file's line when an axis path does not exist in a base
// scenario, an estimator is not in it, or a value makes a run's scenario, setup or estimator
// options invalid (each run is checked as `statebench run` would, before anything runs).
std::vector<SweepRun> ExpandSweep(const SweepSpec& spec, const std::string& code_version,
                                  std::optional<double> duration_override = std::nullopt);

// Runs I of N (1-based I): the runs whose index % N == I - 1.
std::vector<SweepRun> ShardOf(const std::vector<SweepRun>& runs, int shard, int shards);

// "git commit[-dirty]" of the source tree the binary was built from (STATEBENCH_SOURCE_DIR), or
// "statebench <version>" when it is not a git checkout.
std::string CodeVersion();

}  // namespace statebench::app
