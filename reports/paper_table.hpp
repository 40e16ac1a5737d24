// Table I of the paper (Dahal et al., ../shared/paper) side by side with our runs of the suite
// scenarios (scenarios/paper/), as data, Markdown and JSON. Nothing here prints.
//
// Input: each scenario's run.json as `statebench run` writes it (docs/cli.md):
//   {"scenario", "simulated_s", "distance_m", "wall_time_s", "real_time_factor",
//    "estimators": [{"label", "type", "metrics": <metrics.json>}, ...]}
// Output: one section per scenario, one row per metric (RMSE X, Y, yaw, longitudinal velocity,
// APE, pose NEES; for scenarios with a GNSS outage the RMSE during it and the error after it),
// columns paper FG, paper EKF, then every estimator label of the scenario in its order.
// The paper's numbers are kept in one place (PaperValues) with the part of the paper they come
// from.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace statebench::reports {

// A row of the table: the number read from an estimator's metrics (metrics.json).
struct TableMetric {
  std::string id;       // "rmse_x"
  std::string label;    // "RMSE X [m]"
  std::string pointer;  // JSON pointer into the metrics, e.g. "/rmse/x_m"
  int decimals = 3;
  bool magnitude = false;  // report |value| (signed error components)
  // Number of estimates behind the value; 0 (e.g. an estimator that never initialised) makes the
  // value missing rather than a misleading 0.
  std::string count_pointer = "/compared";
};
const std::vector<TableMetric>& TableMetrics();

// A number the paper reports for the experiment one of our scenarios reproduces.
struct PaperValue {
  std::string scenario;   // our scenario name, e.g. "setup2_quadricycle"
  std::string metric;     // TableMetric::id
  std::string estimator;  // "factor_graph" or "ekf"
  double value = 0.0;
  int decimals = 2;    // as printed in the paper
  std::string source;  // where in the paper, e.g. "Table I"
};
const std::vector<PaperValue>& PaperValues();

// One scenario of the suite: its run.json, or why there is none.
struct ScenarioRun {
  std::string scenario;
  std::optional<nlohmann::json> run;
  std::string failure;  // when `run` is empty, e.g. "exit code 2: ..."
};

struct TableRow {
  const TableMetric* metric = nullptr;
  std::optional<double> paper_fg, paper_ekf;
  std::vector<std::optional<double>> ours;  // one per TableSection::labels entry
};

struct TableSection {
  std::string scenario;
  std::string failure;              // empty: the run succeeded
  std::vector<std::string> labels;  // our estimators, scenario order
  std::vector<std::string> types;   // their types
  std::vector<std::string> inputs;  // the sensors each was given ("all sensors" or a list)
  double simulated_s = 0.0, distance_m = 0.0, wall_time_s = 0.0, real_time_factor = 0.0;
  std::vector<TableRow> rows;  // metrics with a value in the paper or in one of our columns
};

struct PaperTable {
  std::vector<TableSection> sections;
};

// Throws nlohmann::json exceptions on a run.json that lacks the fields above.
PaperTable BuildPaperTable(const std::vector<ScenarioRun>& runs);

// "## ..." heading, one table per scenario, then the sources of the paper's numbers.
std::string ToMarkdown(const PaperTable& table);
nlohmann::json ToJson(const PaperTable& table);

}  // namespace statebench::reports
