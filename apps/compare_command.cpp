// statebench compare BASE CANDIDATE [--estimators BASE_EST,CANDIDATE_EST] [--thresholds FILE]
//                    [--out compare.html]
//
// Regression verdicts between two versions (reports/paired_comparison.hpp, docs/regression.md):
// BASE and CANDIDATE are results stores (a .db file, or a sweep's --out folder holding
// results.db) or run folders (holding run.json).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/html_report.hpp"
#include "core/error.hpp"
#include "reports/comparison_json.hpp"
#include "reports/paired_comparison.hpp"
#include "reports/results_store.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage: statebench compare BASE CANDIDATE [--estimators BASE_EST,CANDIDATE_EST]\n"
    "                          [--thresholds FILE] [--out compare.html]\n"
    "  BASE and CANDIDATE: results stores (file, or a sweep folder with results.db) or run\n"
    "  folders (with run.json). Runs are paired by scenario, parameters and seed; per estimator\n"
    "  and metric of the thresholds file (default scenarios/regression/thresholds.yaml): the\n"
    "  paired differences, a Wilcoxon signed-rank test, a bootstrap interval of the median\n"
    "  difference and a verdict (better / worse / no significant change). Prints a Markdown\n"
    "  summary, writes the HTML report with plots of the paired differences with --out.\n"
    "  --estimators: estimator BASE_EST of BASE against CANDIDATE_EST of CANDIDATE (BASE and\n"
    "  CANDIDATE may be the same store: two estimators of one sweep, paired run by run).\n"
    "  Exit code: 0 no metric worse, 1 some metric worse, 2 bad input (no run in common, an\n"
    "  estimator no run has, a bad thresholds file), 3 another failure.\n";

// The runs of a store or of a run folder.
std::vector<reports::RunRecord> LoadRuns(const fs::path& where) {
  std::error_code ec;
  if (fs::is_directory(where, ec)) {
    if (fs::is_regular_file(where / "results.db", ec)) {
      return reports::ResultsStore(where / "results.db", reports::ResultsStore::Access::kRead)
          .Runs();
    }
    const fs::path summary_file = where / "run.json";
    std::ifstream in(summary_file);
    if (!in) {
      throw InputError(where.string() + ": neither a results store (results.db) nor a run "
                       "folder (run.json)");
    }
    nlohmann::json summary;
    try {
      summary = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(summary_file.string() + ": not JSON: " + e.what());
    }
    reports::RunRecord run;
    run.id = where.filename().string();
    run.scenario = summary.value("scenario", "");
    run.seed = summary.value("seed", std::uint64_t{0});
    run.status = "ok";
    for (const nlohmann::json& e : summary.value("estimators", nlohmann::json::array())) {
      const std::string label = e.value("label", "");
      for (const auto& [name, value] : reports::FlattenMetrics(e.value("metrics", nlohmann::json{}))) {
        run.metrics.push_back({label, name, value});
      }
    }
    return {run};
  }
  if (!fs::is_regular_file(where, ec)) throw InputError(where.string() + ": no such store or run folder");
  return reports::ResultsStore(where, reports::ResultsStore::Access::kRead).Runs();
}

fs::path DefaultThresholds() {
  const char* source = std::getenv("STATEBENCH_SOURCE_DIR");
  return fs::path(source ? source : ".") / "scenarios" / "regression" / "thresholds.yaml";
}

}  // namespace

int RunCompare(const std::vector<std::string>& argv) {
  const auto parsed =
      ParseCommand({"compare", kUsage, {}, {"estimators", "thresholds", "out"}, 2, {}}, argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs& args = std::get<CliArgs>(parsed);
  try {
    const fs::path base = args.positional().at(0);
    const fs::path candidate = args.positional().at(1);
    const reports::RegressionThresholds thresholds = reports::LoadRegressionThresholds(
        args.Option("thresholds") ? fs::path(*args.Option("thresholds")) : DefaultThresholds());
    std::vector<reports::RunRecord> base_runs = LoadRuns(base);
    std::vector<reports::RunRecord> candidate_runs = LoadRuns(candidate);
    if (const auto pair = args.Option("estimators")) {
      const std::size_t comma = pair->find(',');
      if (comma == std::string::npos || comma == 0 || comma + 1 == pair->size() ||
          pair->find(',', comma + 1) != std::string::npos) {
        throw InputError("--estimators: expected BASE_EST,CANDIDATE_EST, got '" + *pair + "'");
      }
      const std::string base_estimator = pair->substr(0, comma);
      const std::string candidate_estimator = pair->substr(comma + 1);
      const std::string label = base_estimator + " -> " + candidate_estimator;
      base_runs = reports::SelectEstimator(std::move(base_runs), base_estimator, label,
                                           base.string());
      candidate_runs = reports::SelectEstimator(std::move(candidate_runs), candidate_estimator,
                                                label, candidate.string());
    }
    const reports::Comparison c = reports::CompareRuns(base_runs, candidate_runs, thresholds);
    std::printf("%s", reports::ComparisonMarkdown(c, base.string(), candidate.string()).c_str());
    std::fflush(stdout);
    if (const auto out = args.Option("out")) {
      // The verdict stands whatever happens to the page: a page that cannot be drawn is
      // "another failure" (3) unless a metric is worse (1 says more to a gate).
      try {
        RenderHtmlReport("compare_report",
                         {{"comparison", reports::ComparisonJson(c, base.string(), candidate.string(),
                                                                 thresholds.significance)}},
                         *out);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "error: the HTML report %s: %s\n", out->c_str(), e.what());
        return c.AnyWorse() ? 1 : 3;
      }
    }
    return c.AnyWorse() ? 1 : 0;
  } catch (...) {
    // 1 means "worse", so a CI gate can tell a regression from a failure: bad input is 2,
    // anything else 3.
    const int code = ExitCodeForCurrentException("compare");
    return code == 1 ? 3 : code;
  }
}

}  // namespace statebench::app
