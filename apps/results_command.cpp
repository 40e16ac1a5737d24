// statebench results summary DB [--by AXIS,...] [--metrics NAME,...] [--format text|md|csv|json]
// statebench results merge A.db B.db ... --out ALL.db
//
// Reads results stores written by `statebench sweep` (reports/results_store.hpp).
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "core/error.hpp"
#include "reports/figure_format.hpp"
#include "reports/results_store.hpp"
#include "reports/sweep_statistics.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage: statebench results summary DB [--by AXIS,...] [--metrics NAME,...]\n"
    "                                     [--format text|md|csv|json]\n"
    "       statebench results merge A.db B.db ... --out ALL.db\n"
    "  summary: per estimator and per value of the chosen axes (sweep axes, or 'scenario'),\n"
    "  the run count, failures, mean / median / p95 / max of each metric with a 95 % bootstrap\n"
    "  interval of the mean, and the average pose NEES over the runs (ANEES) with its two-sided\n"
    "  95 % chi-square bounds for that many runs. Metrics are metrics.json keys joined by dots\n"
    "  (default: rmse.x_m, rmse.y_m, rmse.yaw_rad, rmse.v_longitudinal_mps,\n"
    "  ape.translation_m.rmse, nees.pose_6dof_mean, availability.fraction).\n"
    "  merge: the runs of every store in one (a run present twice with different results is an\n"
    "  error); shards of one sweep merge into the store the unsharded sweep would have written.\n";

const std::vector<std::string> kDefaultMetrics = {
    "rmse.x_m",         "rmse.y_m", "rmse.yaw_rad", "rmse.v_longitudinal_mps",
    "ape.translation_m.rmse", "nees.pose_6dof_mean", "availability.fraction"};
constexpr const char* kNeesMetric = "nees.pose_6dof_mean";
constexpr double kPoseNeesDof = 6.0;

struct Group {
  std::string estimator;
  std::vector<std::string> axis_values;
  std::size_t runs = 0;
  std::size_t failed = 0;
  std::size_t unavailable = 0;  // ok runs where the estimator compared no epoch (never started)
  std::map<std::string, std::vector<double>> values;  // metric -> one value per ok run
};

std::string ParameterOf(const reports::RunRecord& r, const std::string& axis) {
  if (axis == "scenario") return r.scenario;
  if (axis == "seed") return std::to_string(r.seed);
  for (const auto& [name, value] : r.parameters) {
    if (name == axis) return value;
  }
  return "";
}

// Sorts axis values numerically when both are numbers.
bool ValueLess(const std::string& a, const std::string& b) {
  char* end_a = nullptr;
  char* end_b = nullptr;
  const double x = std::strtod(a.c_str(), &end_a);
  const double y = std::strtod(b.c_str(), &end_b);
  if (end_a && *end_a == '\0' && end_b && *end_b == '\0' && !a.empty() && !b.empty()) {
    return x < y;
  }
  return a < b;
}

std::vector<Group> GroupRuns(const std::vector<reports::RunRecord>& runs,
                             const std::vector<std::string>& by,
                             const std::vector<std::string>& metrics) {
  std::set<std::string> axes_known = {"scenario", "seed"};
  std::set<std::string> estimators;
  for (const reports::RunRecord& r : runs) {
    for (const auto& [axis, value] : r.parameters) axes_known.insert(axis);
    for (const reports::MetricValue& m : r.metrics) estimators.insert(m.estimator);
  }
  for (const std::string& axis : by) {
    if (!axes_known.count(axis)) {
      std::string known;
      for (const std::string& a : axes_known) known += (known.empty() ? "" : ", ") + a;
      throw std::invalid_argument("--by: no axis '" + axis + "' in the store (axes: " + known +
                                  ")");
    }
  }
  std::map<std::pair<std::string, std::vector<std::string>>, Group> groups;
  const auto key_less = [](const std::vector<std::string>& a, const std::vector<std::string>& b) {
    return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(), ValueLess);
  };
  for (const reports::RunRecord& r : runs) {
    std::vector<std::string> values;
    for (const std::string& axis : by) values.push_back(ParameterOf(r, axis));
    for (const std::string& estimator : estimators) {
      Group& g = groups[{estimator, values}];
      g.estimator = estimator;
      g.axis_values = values;
      ++g.runs;
      if (r.status != "ok") {
        ++g.failed;
        continue;
      }
      // An estimator that never produced an estimate scores 0 everywhere in metrics.json; its
      // figures are unavailable, not perfect.
      bool compared_any = true;
      for (const reports::MetricValue& m : r.metrics) {
        if (m.estimator == estimator && m.name == "compared") compared_any = m.value > 0.0;
      }
      if (!compared_any) {
        ++g.unavailable;
        continue;
      }
      for (const std::string& metric : metrics) {
        double value = std::nan("");
        for (const reports::MetricValue& m : r.metrics) {
          if (m.estimator == estimator && m.name == metric) value = m.value;
        }
        g.values[metric].push_back(value);
      }
    }
  }
  std::vector<Group> out;
  for (auto& [key, g] : groups) out.push_back(std::move(g));
  std::stable_sort(out.begin(), out.end(), [&](const Group& a, const Group& b) {
    if (a.estimator != b.estimator) return a.estimator < b.estimator;
    return key_less(a.axis_values, b.axis_values);
  });
  return out;
}

std::string Label(const Group& g) {
  std::string label = g.estimator;
  for (const std::string& v : g.axis_values) label += " " + v;
  return label;
}

int PrintSummary(const std::vector<reports::RunRecord>& runs, const std::vector<std::string>& by,
                 const std::vector<std::string>& metrics, const std::string& format) {
  const std::vector<Group> groups = GroupRuns(runs, by, metrics);
  nlohmann::json json = nlohmann::json::array();
  if (format == "csv") {
    std::printf("estimator");
    for (const std::string& axis : by) std::printf(",%s", axis.c_str());
    std::printf(",runs,failed,unavailable,metric,count,mean,mean_ci_low,mean_ci_high,median,p95,max,"
                "anees_low,anees_high\n");
  }
  for (const std::string& metric : metrics) {
    const bool nees = metric == kNeesMetric;
    if (format == "text" || format == "md") {
      std::printf("\n%s%s%s\n\n", format == "md" ? "### " : "", metric.c_str(),
                  nees ? " (ANEES: mean over runs; bounds: 95 % chi-square for that many runs)"
                       : "");
      std::string head = "| estimator";
      for (const std::string& axis : by) head += " | " + axis;
      head += " | runs | failed | no estimate | mean | 95% CI of mean | median | p95 | max |";
      if (nees) head += " ANEES bounds | consistent |";
      if (format == "md") {
        std::printf("%s\n|", head.c_str());
        const std::size_t columns = 8 + by.size() + (nees ? 2 : 0) + 1;
        for (std::size_t c = 0; c < columns; ++c) std::printf("---|");
        std::printf("\n");
      } else {
        std::printf("%-28s %5s %6s %6s %10s %23s %10s %10s %10s%s\n", "estimator / axes",
                    "runs", "failed", "no est", "mean", "95% CI of mean", "median", "p95", "max",
                    nees ? "   ANEES bounds      consistent" : "");
      }
    }
    for (const Group& g : groups) {
      const auto it = g.values.find(metric);
      const reports::MetricSummary s =
          reports::Summarize(it == g.values.end() ? std::vector<double>{} : it->second);
      reports::ChiSquareBounds bounds{std::nan(""), std::nan("")};
      std::string verdict = "-";
      if (nees && s.count > 0) {
        bounds = reports::AverageNeesBounds(s.count, kPoseNeesDof);
        verdict = s.mean < bounds.low ? "no (under-confident)"
                  : s.mean > bounds.high ? "no (over-confident)"
                                         : "yes";
      }
      const std::string ci = "[" + reports::FormatFigure(s.mean_ci_low) + ", " + reports::FormatFigure(s.mean_ci_high) + "]";
      const std::string bound_text = "[" + reports::FormatFigure(bounds.low) + ", " + reports::FormatFigure(bounds.high) + "]";
      if (format == "csv") {
        std::printf("%s", g.estimator.c_str());
        for (const std::string& v : g.axis_values) std::printf(",%s", v.c_str());
        std::printf(",%zu,%zu,%zu,%s,%zu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
                    g.runs, g.failed, g.unavailable, metric.c_str(), s.count, s.mean, s.mean_ci_low, s.mean_ci_high,
                    s.median, s.p95, s.max, bounds.low, bounds.high);
      } else if (format == "json") {
        nlohmann::json row = {{"estimator", g.estimator}, {"runs", g.runs},
                              {"failed", g.failed},       {"unavailable", g.unavailable},
                              {"metric", metric},
                              {"count", s.count},         {"mean", s.mean},
                              {"mean_ci", {s.mean_ci_low, s.mean_ci_high}},
                              {"median", s.median},       {"p95", s.p95},
                              {"max", s.max}};
        for (std::size_t a = 0; a < by.size(); ++a) row["axes"][by[a]] = g.axis_values[a];
        if (nees) row["anees_bounds"] = {bounds.low, bounds.high};
        json.push_back(row);
      } else if (format == "md") {
        std::printf("| %s", g.estimator.c_str());
        for (const std::string& v : g.axis_values) std::printf(" | %s", v.c_str());
        std::printf(" | %zu | %zu | %zu | %s | %s | %s | %s | %s |", g.runs, g.failed, g.unavailable,
                    reports::FormatFigure(s.mean).c_str(), ci.c_str(), reports::FormatFigure(s.median).c_str(), reports::FormatFigure(s.p95).c_str(),
                    reports::FormatFigure(s.max).c_str());
        if (nees) std::printf(" %s | %s |", bound_text.c_str(), verdict.c_str());
        std::printf("\n");
      } else {
        std::printf("%-28s %5zu %6zu %6zu %10s %23s %10s %10s %10s", Label(g).c_str(), g.runs,
                    g.failed, g.unavailable, reports::FormatFigure(s.mean).c_str(), ci.c_str(), reports::FormatFigure(s.median).c_str(),
                    reports::FormatFigure(s.p95).c_str(), reports::FormatFigure(s.max).c_str());
        if (nees) std::printf("   %-17s %s", bound_text.c_str(), verdict.c_str());
        std::printf("\n");
      }
    }
  }
  if (format == "json") std::printf("%s\n", json.dump(2).c_str());
  std::size_t failed = 0;
  for (const reports::RunRecord& r : runs) failed += r.status != "ok";
  if (format == "text" || format == "md") {
    std::printf("\n%zu runs, %zu failed\n", runs.size(), failed);
    for (const reports::RunRecord& r : runs) {
      if (r.status != "ok") std::printf("  failed %s: %s\n", r.id.c_str(), r.error.c_str());
    }
  }
  return 0;
}

int Summary(const std::vector<std::string>& argv) {
  const auto parsed = ParseCommand(
      {"results summary", kUsage, {}, {"by", "metrics", "format"}, 1, {}}, argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs& args = std::get<CliArgs>(parsed);
  const fs::path file = args.positional().at(0);
  const std::string format = args.Option("format").value_or("text");
  if (format != "text" && format != "md" && format != "csv" && format != "json") {
    throw std::invalid_argument("--format: expected text, md, csv or json, got '" + format + "'");
  }
  const std::vector<std::string> metrics =
      args.Option("metrics") ? SplitList(*args.Option("metrics")) : kDefaultMetrics;
  const reports::ResultsStore store(file, reports::ResultsStore::Access::kRead);
  return PrintSummary(store.Runs(), SplitList(args.Option("by").value_or("")), metrics, format);
}

int Merge(const std::vector<std::string>& argv) {
  std::size_t positional = 0;
  for (std::size_t i = 0; i < argv.size(); ++i) {
    if (argv[i] == "--out") {
      ++i;
    } else if (argv[i].rfind("--", 0) != 0) {
      ++positional;
    }
  }
  const auto parsed = ParseCommand(
      {"results merge", kUsage, {}, {"out"}, std::max<std::size_t>(positional, 1), {"out"}}, argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs& args = std::get<CliArgs>(parsed);
  std::vector<fs::path> inputs(args.positional().begin(), args.positional().end());
  const fs::path out = *args.Option("out");
  for (const fs::path& input : inputs) {
    std::error_code ec;
    if (fs::exists(out, ec) && fs::equivalent(input, out, ec)) {
      throw std::invalid_argument("--out: " + out.string() + " is also an input");
    }
  }
  const std::size_t written = reports::MergeStores(inputs, out);
  std::printf("merged %zu stores into %s: %zu runs written\n", inputs.size(), out.c_str(),
              written);
  return 0;
}

}  // namespace

int RunResults(const std::vector<std::string>& argv) {
  try {
    if (argv.empty() || argv[0] == "--help" || argv[0] == "-h") {
      std::fprintf(argv.empty() ? stderr : stdout, "%s", kUsage);
      return argv.empty() ? 2 : 0;
    }
    const std::vector<std::string> rest(argv.begin() + 1, argv.end());
    if (argv[0] == "summary") return Summary(rest);
    if (argv[0] == "merge") return Merge(rest);
    std::fprintf(stderr, "statebench results: unknown subcommand '%s'\n%s", argv[0].c_str(),
                 kUsage);
    return 2;
  } catch (...) {
    return ExitCodeForCurrentException("results");
  }
}

}  // namespace statebench::app
