// The results store of sweeps (docs/results-store.md): one SQLite file in WAL mode with the
// sweeps, their runs (parameters, seed, code version, status, exit code, error, wall and CPU
// time, host), every figure of each run's metrics and the paths of its files.
//
// A run's rows are written in one transaction when it ends (WriteRun), so a sweep killed at any
// moment leaves complete runs only. Only the sweep process writes; readers may read meanwhile.
// Errors are thrown as InputError naming the file and SQLite's message; nothing prints.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace statebench::reports {

struct MetricValue {
  std::string estimator;
  std::string name;  // flattened metrics.json key: "rmse.x_m", "outages[0].error_end_m"
  double value = 0.0;
  bool operator==(const MetricValue&) const = default;
};

struct Artifact {
  std::string estimator;  // "" for the run's own files
  std::string kind;       // estimate, diagnostics, metrics, run_summary, stderr, scenario
  std::string path;
  bool operator==(const Artifact&) const = default;
};

struct RunRecord {
  std::string id;
  std::string sweep;
  std::string scenario;
  std::uint64_t seed = 0;
  std::vector<std::pair<std::string, std::string>> parameters;  // axis, value
  std::string code_version;
  std::string status;  // "ok" or "failed"
  int exit_code = 0;
  std::string error;  // the failure's message (last lines of stderr), empty when ok
  double wall_s = 0.0;
  double cpu_s = 0.0;
  std::string host;
  std::string finished_at;  // ISO 8601, UTC
  std::string run_dir;
  nlohmann::json cache = nlohmann::json::object();  // stage cache hits of the run
  std::vector<MetricValue> metrics;
  std::vector<Artifact> artifacts;
};

struct SweepRecord {
  std::string name;
  std::string file;
  std::string definition;  // the sweep file's text
  std::string code_version;
  std::string host;
  std::string shard;  // "2/3", "" when not sharded
  std::string started_at;
};

class ResultsStore {
 public:
  // The layout of the tables (SQLite's PRAGMA user_version; 0 in stores written before the
  // version was recorded, which have this same layout).
  static constexpr int kSchemaVersion = 1;

  // kWrite opens or creates the store (schema, WAL mode); kRead opens an existing store without
  // writing to it (no schema, no journal-mode switch: a reader never takes the write lock a
  // sweep writing the same store needs). Throws InputError for a missing store (kRead), a store
  // of a newer schema version or an SQLite file that is not a results store, naming the file.
  enum class Access { kWrite, kRead };
  explicit ResultsStore(const std::filesystem::path& file, Access access = Access::kWrite);
  ~ResultsStore();
  ResultsStore(const ResultsStore&) = delete;
  ResultsStore& operator=(const ResultsStore&) = delete;

  void AddSweep(const SweepRecord& sweep);
  std::vector<SweepRecord> Sweeps() const;

  // Writes (or replaces) a run and all its rows in one transaction.
  void WriteRun(const RunRecord& run);
  // Ids of the runs whose status is ok.
  std::set<std::string> CompletedRunIds() const;
  // Every run with its metrics and artifacts, ordered by id.
  std::vector<RunRecord> Runs() const;
  std::optional<RunRecord> Run(const std::string& id) const;

  const std::filesystem::path& file() const { return file_; }

 private:
  struct Db;
  std::filesystem::path file_;
  std::unique_ptr<Db> db_;
};

// Every numeric leaf of a metrics.json document, keys joined by '.', list elements as [i]
// (strings, and the identifying fields seed and estimator, are left out).
std::vector<std::pair<std::string, double>> FlattenMetrics(const nlohmann::json& metrics);

// Timing figures (solve times): they vary from one execution of a run to the next.
bool IsTimingMetric(const std::string& name);

// Two values of one metric agree: equal to 1e-9 relative (a run repeated on another machine
// may differ in its last bits through the system's libm), or both missing.
bool SameMetricValue(double a, double b);

// Merges the stores `inputs` into `output` (created when missing). A run present more than once
// must have the same status and metric values everywhere (timing figures aside, values to
// SameMetricValue), else InputError names it, the metric and the two stores; a failed copy gives
// way to a successful one. Returns the number of runs written.
std::size_t MergeStores(const std::vector<std::filesystem::path>& inputs,
                        const std::filesystem::path& output);

}  // namespace statebench::reports
