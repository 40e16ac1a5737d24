// statebench report RUN_DIR|DB --out report.html [--by AXIS] [--metrics NAME,...] [--worst N]
//
// HTML reports with plots (docs/reports.md): of one run folder written by `statebench run`, or
// of a sweep's results store (a .db file, or the sweep's --out folder holding results.db) with
// the worst runs' own reports alongside. The data and statistics are gathered here; the pages
// are drawn by the report package (apps/html_report.hpp).
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/html_report.hpp"
#include "core/error.hpp"
#include "reports/results_store.hpp"
#include "reports/sweep_report_data.hpp"
#include "reports/sweep_statistics.hpp"
#include "simulator/scenario_resolution.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage: statebench report RUN_DIR --out report.html\n"
    "       statebench report DB --out sweep.html [--by AXIS] [--metrics NAME,...] [--worst N]\n"
    "  RUN_DIR: a folder written by 'statebench run' (run.json): trajectories over the road\n"
    "  network with GNSS fixes and outages, errors against time with each estimator's 3-sigma\n"
    "  band, NEES with its chi-square bounds, measurement verdicts over time, solve times, the\n"
    "  scenario and options, the metrics.\n"
    "  DB: a sweep's results store (results.db, or the sweep's --out folder): per metric the\n"
    "  distribution over the runs per value of --by (default: the sweep's first axis) and\n"
    "  estimator, the ANEES of each cell against its chi-square bounds, the failed runs, and the\n"
    "  --worst N (default 3) runs of each metric, each with its own report in <out>_runs/.\n"
    "  One self-contained HTML file (no network). Exit code 2 for bad input, 1 on failure.\n";

// The average NEES bounds of one epoch (two-sided 95 %): what a consistent estimator's NEES
// stays inside 95 % of the time.
nlohmann::json EpochNeesBounds() {
  const reports::ChiSquareBounds pose = reports::AverageNeesBounds(1, 6.0);
  const reports::ChiSquareBounds position = reports::AverageNeesBounds(1, 3.0);
  return {{"pose", {pose.low, pose.high}}, {"position", {position.low, position.high}}};
}

nlohmann::json ReadJson(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot read");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string() + ": not JSON: " + e.what());
  }
}

// The scenario a run used, as text: its own copy in the run folder (a sweep's runs have one),
// else the file run.json names, resolved now (sensor setup and estimator options inline), with a
// note saying so.
nlohmann::json ScenarioOf(const fs::path& run_dir, const nlohmann::json& summary) {
  const fs::path copy = run_dir / "scenario.yaml";
  if (fs::is_regular_file(copy)) {
    std::ifstream in(copy);
    std::stringstream text;
    text << in.rdbuf();
    return {{"text", text.str()}, {"source", copy.string()}, {"note", ""}};
  }
  const std::string named = summary.value("file", "");
  if (named.empty()) {
    return {{"text", ""}, {"source", ""}, {"note", "run.json names no scenario file"}};
  }
  const char* source_dir = std::getenv("STATEBENCH_SOURCE_DIR");
  fs::path file = named;
  if (!fs::is_regular_file(file) && source_dir && file.is_relative()) file = fs::path(source_dir) / named;
  if (!fs::is_regular_file(file)) {
    return {{"text", ""},
            {"source", named},
            {"note", "the run folder holds no copy of its scenario and " + named +
                         " is not found from here"}};
  }
  try {
    YAML::Emitter out;
    out << sim::ResolveScenario(file);
    return {{"text", std::string(out.c_str()) + "\n"},
            {"source", fs::absolute(file).string()},
            {"note", "The run folder holds no copy of its scenario: this is " + named +
                         " as it is now, resolved (sensor setup and estimator options inline); "
                         "it may differ from what the run used if the file changed since."}};
  } catch (const std::exception& e) {
    return {{"text", ""}, {"source", named}, {"note", std::string("cannot resolve: ") + e.what()}};
  }
}

void RunReport(const fs::path& run_dir, const fs::path& out) {
  const nlohmann::json summary = ReadJson(run_dir / "run.json");
  nlohmann::json job = {{"run_dir", fs::absolute(run_dir).string()},
                        {"nees_bounds", EpochNeesBounds()},
                        {"scenario", ScenarioOf(run_dir, summary)}};
  RenderHtmlReport("run_report", job, out);
}

void SweepReport(const fs::path& store_file, const CliArgs& args, const fs::path& out) {
  reports::SweepReportOptions options;
  if (const auto by = args.Option("by")) options.by = *by;
  if (const auto metrics = args.Option("metrics")) options.metrics = SplitList(*metrics);
  const std::uint64_t worst = args.Unsigned("worst").value_or(3);
  const reports::ResultsStore store(store_file, reports::ResultsStore::Access::kRead);
  nlohmann::json job = {{"data", reports::SweepReportData(store, options)},
                        {"nees_bounds", EpochNeesBounds()},
                        {"worst", worst}};
  RenderHtmlReport("sweep_report", job, out);
}

}  // namespace

int RunReportCommand(const std::vector<std::string>& argv) {
  const auto parsed =
      ParseCommand({"report", kUsage, {}, {"out", "by", "metrics", "worst"}, 1, {"out"}}, argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs& args = std::get<CliArgs>(parsed);
  try {
    const fs::path input = args.positional().at(0);
    const fs::path out = *args.Option("out");
    std::error_code ec;
    const bool run_folder = fs::is_regular_file(input / "run.json", ec);
    fs::path store;
    if (fs::is_regular_file(input, ec)) {
      store = input;
    } else if (fs::is_regular_file(input / "results.db", ec)) {
      store = input / "results.db";
    } else if (!run_folder) {
      throw InputError(input.string() + (fs::exists(input, ec)
                                             ? ": neither a run folder (run.json) nor a results "
                                               "store (results.db)"
                                             : ": no such run folder or results store"));
    }
    if (run_folder) {
      for (const char* option : {"by", "metrics", "worst"}) {
        if (args.Option(option)) {
          throw std::invalid_argument(std::string("--") + option +
                                      " is for a sweep's results store, not a run folder");
        }
      }
      RunReport(input, out);
    } else {
      SweepReport(store, args, out);
    }
    std::printf("report: %s (%.1f MB)\n", out.c_str(),
                static_cast<double>(fs::file_size(out)) / 1e6);
    return 0;
  } catch (...) {
    return ExitCodeForCurrentException("report");
  }
}

}  // namespace statebench::app
