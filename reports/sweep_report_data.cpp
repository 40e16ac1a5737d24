#include "reports/sweep_report_data.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "core/error.hpp"
#include "reports/sweep_statistics.hpp"

namespace statebench::reports {
namespace {

nlohmann::json Number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }

std::string ValueOf(const RunRecord& r, const std::string& axis) {
  if (axis == "scenario") return r.scenario;
  if (axis == "seed") return std::to_string(r.seed);
  for (const auto& [name, value] : r.parameters) {
    if (name == axis) return value;
  }
  return "";
}

std::string Joined(const std::set<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// Degrees of freedom of the NEES metrics the report bounds.
const std::map<std::string, double>& NeesMetrics() {
  static const std::map<std::string, double> dof = {{"nees.pose_6dof_mean", 6.0},
                                                    {"nees.position_3dof_mean", 3.0}};
  return dof;
}

}  // namespace

const std::vector<std::string>& DefaultSweepReportMetrics() {
  static const std::vector<std::string> metrics = {
      "rmse.x_m",          "rmse.y_m",          "rmse.yaw_rad",          "rmse.v_longitudinal_mps",
      "ape.translation_m.rmse", "nees.pose_6dof_mean", "availability.fraction"};
  return metrics;
}

nlohmann::json SweepReportData(const ResultsStore& store, const SweepReportOptions& options) {
  const std::vector<RunRecord> runs = store.Runs();
  if (runs.empty()) throw InputError(store.file().string() + ": the store holds no run");
  const std::vector<std::string> metrics =
      options.metrics.empty() ? DefaultSweepReportMetrics() : options.metrics;

  std::set<std::string> axes, scenarios, estimators, metric_names;
  std::vector<std::string> axis_order;
  for (const RunRecord& r : runs) {
    scenarios.insert(r.scenario);
    for (const auto& [axis, value] : r.parameters) {
      if (axes.insert(axis).second) axis_order.push_back(axis);
    }
    for (const MetricValue& m : r.metrics) {
      estimators.insert(m.estimator);
      metric_names.insert(m.name);
    }
  }
  std::string by = options.by;
  if (by.empty()) {
    if (!axis_order.empty()) {
      by = axis_order.front();
    } else if (scenarios.size() > 1) {
      by = "scenario";
    }
  } else if (by != "scenario" && by != "seed" && !axes.count(by)) {
    throw InputError(store.file().string() + ": no axis '" + by + "' in the store (axes: " +
                     Joined(axes) + (axes.empty() ? "" : ", ") + "scenario, seed)");
  }
  if (!metric_names.empty()) {
    for (const std::string& m : metrics) {
      if (!metric_names.count(m)) {
        throw InputError(store.file().string() + ": no metric '" + m +
                         "' in the store (metrics.json keys joined by dots, e.g. rmse.x_m, "
                         "ape.translation_m.rmse, nees.pose_6dof_mean)");
      }
    }
  }

  nlohmann::json sweeps = nlohmann::json::array();
  for (const SweepRecord& s : store.Sweeps()) {
    sweeps.push_back({{"name", s.name},
                      {"file", s.file},
                      {"code_version", s.code_version},
                      {"host", s.host},
                      {"shard", s.shard},
                      {"started_at", s.started_at}});
  }
  nlohmann::json run_list = nlohmann::json::array();
  for (const RunRecord& r : runs) {
    nlohmann::json parameters = nlohmann::json::object();
    for (const auto& [axis, value] : r.parameters) parameters[axis] = value;
    nlohmann::json per_estimator = nlohmann::json::object();
    for (const MetricValue& m : r.metrics) {
      if (m.name != "compared" &&
          std::find(metrics.begin(), metrics.end(), m.name) == metrics.end()) {
        continue;
      }
      per_estimator[m.estimator][m.name] = Number(m.value);
    }
    run_list.push_back({{"id", r.id},
                        {"scenario", r.scenario},
                        {"seed", r.seed},
                        {"parameters", parameters},
                        {"cell", by.empty() ? "" : ValueOf(r, by)},
                        {"status", r.status},
                        {"exit_code", r.exit_code},
                        {"error", r.error},
                        {"wall_s", Number(r.wall_s)},
                        {"cpu_s", Number(r.cpu_s)},
                        {"host", r.host},
                        {"run_dir", r.run_dir},
                        {"metrics", per_estimator}});
  }
  nlohmann::json bounds = nlohmann::json::object();
  for (const std::string& m : metrics) {
    const auto it = NeesMetrics().find(m);
    if (it == NeesMetrics().end()) continue;
    nlohmann::json by_runs = nlohmann::json::array();
    for (std::size_t n = 1; n <= std::max<std::size_t>(runs.size(), 1); ++n) {
      const ChiSquareBounds b = AverageNeesBounds(n, it->second);
      by_runs.push_back({b.low, b.high});
    }
    bounds[m] = {{"dof", it->second}, {"by_runs", by_runs}};
  }
  return {{"store", store.file().string()},
          {"sweeps", sweeps},
          {"axes", axis_order},
          {"by", by},
          {"metrics", metrics},
          {"estimators", estimators},
          {"runs", run_list},
          {"nees_bounds", bounds}};
}

}  // namespace statebench::reports
