// Regression verdicts between two versions: runs of a base and a candidate store paired by
// scenario, parameters and seed (not by code version), and per estimator and metric the paired
// differences, a Wilcoxon signed-rank test, a seeded bootstrap interval of the median
// difference, and a verdict against thresholds (docs/regression.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "reports/results_store.hpp"
#include "reports/sweep_statistics.hpp"

namespace statebench::reports {

// How a metric is judged (scenarios/regression/thresholds.yaml).
struct MetricThreshold {
  std::string name;          // metrics.json key path, e.g. rmse.x_m
  bool lower_is_better = true;
  // When set, closer to this value is better (a NEES and its degrees of freedom): the paired
  // differences are those of the distances |value - target|.
  std::optional<double> target;
  double absolute = 0.0;     // a change smaller than this is never a verdict
  double relative = 0.0;     // nor one smaller than this fraction of the base median
};

struct RegressionThresholds {
  double significance = 0.05;  // two-sided level of the signed-rank test
  std::vector<MetricThreshold> metrics;
};

// Reads the thresholds file; throws InputError "file:line:col: field ...".
RegressionThresholds LoadRegressionThresholds(const std::filesystem::path& file);

// Two-sided p-value of the Wilcoxon signed-rank test of the differences (zeros dropped, ties
// averaged): exact for up to 20 non-zero differences, normal approximation with tie correction
// above. 1 when there is no non-zero difference.
double WilcoxonSignedRankP(const std::vector<double>& differences);

// 95 % percentile bootstrap interval of the median (seeded: same input, same interval).
Interval BootstrapMedianInterval(const std::vector<double>& values, std::uint64_t seed = 1,
                                 int resamples = 2000);

enum class Verdict { kBetter, kWorse, kNoChange, kNoData };
const char* VerdictName(Verdict v);

struct MetricComparison {
  std::string estimator;
  std::string metric;
  std::string better;             // lower, higher or closer (to target), as in the thresholds
  std::optional<double> target;
  std::size_t pairs = 0;  // pairs where both values are finite
  double base_median = 0.0;
  double candidate_median = 0.0;
  double median_difference = 0.0;  // candidate - base
  Interval difference_interval;
  double p_value = 1.0;
  double threshold = 0.0;  // the change that counts: max(absolute, relative * |base median|)
  Verdict verdict = Verdict::kNoData;
  // The pairs that entered, in pairing-key order: the values of both sides and their difference
  // as judged (candidate - base, or of the distances to the target).
  struct Pair {
    std::string key;  // PairingKey
    double base = 0.0;
    double candidate = 0.0;
    double difference = 0.0;
  };
  std::vector<Pair> paired;
};

struct Comparison {
  std::size_t base_runs = 0;
  std::size_t candidate_runs = 0;
  std::size_t pairs = 0;
  std::vector<std::string> unpaired;  // run descriptions found on one side only
  std::vector<MetricComparison> metrics;
  bool AnyWorse() const;
};

// The pairing key of a run: scenario, parameters (by axis name) and seed.
std::string PairingKey(const RunRecord& run);

// Pairs the ok runs of both sides and judges each (estimator, metric) of the thresholds that
// both sides have. Throws InputError when no run pairs.
Comparison CompareRuns(const std::vector<RunRecord>& base, const std::vector<RunRecord>& candidate,
                       const RegressionThresholds& thresholds);

// Two estimators of the same runs compared with each other (statebench compare --estimators):
// the runs with only `estimator`'s metrics kept, relabelled `label`, so that CompareRuns pairs
// them with another estimator's runs relabelled the same. Throws InputError naming `where` and
// the estimators it has when no run has `estimator`.
std::vector<RunRecord> SelectEstimator(std::vector<RunRecord> runs, const std::string& estimator,
                                       const std::string& label, const std::string& where);

// Markdown summary (a pull-request comment). The HTML report with plots is drawn from
// ComparisonJson (reports/comparison_json.hpp) by the compare report (docs/reports.md).
std::string ComparisonMarkdown(const Comparison& c, const std::string& base_name,
                               const std::string& candidate_name);

}  // namespace statebench::reports
