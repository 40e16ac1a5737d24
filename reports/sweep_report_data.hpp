// What the sweep report (docs/reports.md) draws from a results store, as JSON: every run with its
// parameters, status, error and the chosen metrics of each estimator, and the chi-square bounds
// of the average NEES for any number of runs (sweep_statistics.hpp), so the report's cells need
// no statistics of their own.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "reports/results_store.hpp"

namespace statebench::reports {

struct SweepReportOptions {
  // Axis the cells are split by: a sweep axis, "scenario" or "seed". Empty: the store's first
  // sweep axis (the first parameter of the first run), else "scenario" when the store holds
  // several scenarios, else none (one cell per estimator).
  std::string by;
  // Flattened metrics.json keys; empty: DefaultSweepReportMetrics().
  std::vector<std::string> metrics;
};

// RMSE of x, y, yaw and longitudinal velocity, APE, pose NEES, availability (as results
// summary).
const std::vector<std::string>& DefaultSweepReportMetrics();

// {"store", "sweeps": [{name, file, code_version, host, shard, started_at}], "axes": [...],
//  "by": axis or "", "metrics": [...], "estimators": [...],
//  "runs": [{"id", "scenario", "seed", "parameters": {axis: value}, "cell": value of `by`,
//            "status", "exit_code", "error", "wall_s", "cpu_s", "host", "run_dir",
//            "metrics": {estimator: {"compared": n, metric: value or null}}}],
//  "nees_bounds": {metric: {"dof", "by_runs": [[low, high] for 1, 2, ... runs]}}}
// for the NEES metrics among `metrics` (pose 6 dof, position 3 dof; two-sided 95 %).
// Throws InputError for a store without runs, an axis the store does not have or a metric no
// successful run has.
nlohmann::json SweepReportData(const ResultsStore& store, const SweepReportOptions& options);

}  // namespace statebench::reports
