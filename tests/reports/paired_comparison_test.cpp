#include "reports/paired_comparison.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"

namespace statebench::reports {
namespace {

TEST(WilcoxonSignedRank, ExactAndNormalApproximation) {
  // Ten positive differences: W+ takes its largest value, P = 2 / 2^10.
  std::vector<double> d;
  for (int i = 1; i <= 10; ++i) d.push_back(i * 0.1);
  EXPECT_NEAR(WilcoxonSignedRankP(d), 2.0 / 1024.0, 1e-12);
  // Symmetric differences: no evidence at all.
  EXPECT_NEAR(WilcoxonSignedRankP({-1, 1, -2, 2, -3, 3}), 1.0, 1e-12);
  EXPECT_EQ(WilcoxonSignedRankP({0.0, 0.0}), 1.0);
  // Nine paired differences, W+ = 40: exact p = 40 / 1024 (enumerated independently).
  const double p = WilcoxonSignedRankP({1.83 - 0.878, 0.50 - 0.647, 1.62 - 0.598, 2.48 - 2.05,
                                        1.68 - 1.06, 1.88 - 1.29, 1.55 - 1.06, 3.06 - 3.14,
                                        1.30 - 1.29});
  EXPECT_NEAR(p, 0.0390625, 1e-12);
  // Thirty positive differences: the normal approximation, far below 1e-5.
  std::vector<double> many;
  for (int i = 1; i <= 30; ++i) many.push_back(i);
  EXPECT_LT(WilcoxonSignedRankP(many), 1e-5);
}

TEST(BootstrapMedianInterval, SeededAndAroundTheMedian) {
  std::vector<double> v;
  for (int i = 0; i < 50; ++i) v.push_back(std::sin(i) + 2.0);
  const Interval a = BootstrapMedianInterval(v);
  const Interval b = BootstrapMedianInterval(v);
  EXPECT_EQ(a.low, b.low);
  EXPECT_EQ(a.high, b.high);
  EXPECT_LT(a.low, 2.0 + std::sin(0.3));
  EXPECT_GT(a.high, 2.0);
}

RunRecord MakeRun(std::uint64_t seed, double x, double nees) {
  RunRecord r;
  r.id = "r" + std::to_string(seed);
  r.scenario = "s";
  r.seed = seed;
  r.parameters = {{"cep_m", "2"}};
  r.status = "ok";
  r.metrics = {{"fg", "rmse.x_m", x}, {"fg", "nees.pose_6dof_mean", nees}};
  return r;
}

RegressionThresholds Thresholds() {
  RegressionThresholds t;
  t.metrics = {{"rmse.x_m", true, std::nullopt, 0.01, 0.05},
               {"nees.pose_6dof_mean", true, 6.0, 0.5, 0.0}};
  return t;
}

TEST(CompareRuns, VerdictsFollowTheDifferencesAndTheThresholds) {
  std::vector<RunRecord> base, worse, same, tiny, better;
  for (std::uint64_t s = 1; s <= 10; ++s) {
    const double x = 0.2 + 0.01 * std::sin(static_cast<double>(s));
    base.push_back(MakeRun(s, x, 9.0));
    worse.push_back(MakeRun(s, x + 0.05 + 0.001 * s, 9.0));
    same.push_back(MakeRun(s, x, 9.0));
    tiny.push_back(MakeRun(s, x + 0.002, 9.0));           // significant, below the threshold
    better.push_back(MakeRun(s, x - 0.03 - 0.001 * s, 6.5));  // and NEES closer to 6
  }
  const auto verdict = [](const Comparison& c, const std::string& metric) {
    for (const MetricComparison& m : c.metrics) {
      if (m.metric == metric) return m.verdict;
    }
    return Verdict::kNoData;
  };
  const Comparison w = CompareRuns(base, worse, Thresholds());
  EXPECT_EQ(w.pairs, 10u);
  EXPECT_EQ(verdict(w, "rmse.x_m"), Verdict::kWorse);
  EXPECT_TRUE(w.AnyWorse());
  EXPECT_NE(ComparisonMarkdown(w, "a", "b").find("REGRESSION"), std::string::npos);
  const Comparison s = CompareRuns(base, same, Thresholds());
  EXPECT_EQ(verdict(s, "rmse.x_m"), Verdict::kNoChange);
  EXPECT_FALSE(s.AnyWorse());
  EXPECT_EQ(verdict(CompareRuns(base, tiny, Thresholds()), "rmse.x_m"), Verdict::kNoChange);
  const Comparison b = CompareRuns(base, better, Thresholds());
  EXPECT_EQ(verdict(b, "rmse.x_m"), Verdict::kBetter);
  EXPECT_EQ(verdict(b, "nees.pose_6dof_mean"), Verdict::kBetter);
}

TEST(CompareRuns, RunsPairByScenarioParametersAndSeedOnly) {
  std::vector<RunRecord> base = {MakeRun(1, 0.1, 6), MakeRun(2, 0.1, 6)};
  std::vector<RunRecord> candidate = {MakeRun(2, 0.1, 6), MakeRun(3, 0.1, 6)};
  candidate[0].code_version = "other";
  candidate[0].id = "another id";
  const Comparison c = CompareRuns(base, candidate, Thresholds());
  EXPECT_EQ(c.pairs, 1u);
  EXPECT_EQ(c.unpaired.size(), 2u);
  candidate = {MakeRun(1, 0.1, 6)};
  candidate[0].parameters = {{"cep_m", "4"}};
  EXPECT_THROW(CompareRuns(base, candidate, Thresholds()), InputError);
}

TEST(CompareRuns, TwoEstimatorsOfTheSameRunsCompareWithEachOther) {
  // One store, two estimators: "fg" better than "ekf" on every run by construction, so the
  // paired verdict of ekf -> fg is "better" with 12 pairs; the other way round "worse".
  std::vector<RunRecord> runs;
  for (std::uint64_t s = 1; s <= 12; ++s) {
    RunRecord r = MakeRun(s, 0.2 + 0.01 * s, 6.0);
    r.metrics.push_back({"ekf", "rmse.x_m", 0.3 + 0.012 * s});
    r.metrics.push_back({"ekf", "nees.pose_6dof_mean", 6.0});
    runs.push_back(r);
  }
  const std::string label = "ekf -> fg";
  const Comparison c = CompareRuns(SelectEstimator(runs, "ekf", label, "store"),
                                   SelectEstimator(runs, "fg", label, "store"), Thresholds());
  ASSERT_EQ(c.pairs, 12u);
  ASSERT_EQ(c.metrics.size(), 2u);
  EXPECT_EQ(c.metrics[0].estimator, label);
  EXPECT_EQ(c.metrics[0].metric, "rmse.x_m");
  EXPECT_EQ(c.metrics[0].verdict, Verdict::kBetter);
  EXPECT_EQ(c.metrics[0].pairs, 12u);
  EXPECT_EQ(c.metrics[1].verdict, Verdict::kNoChange);  // NEES equal on both
  const Comparison reverse = CompareRuns(SelectEstimator(runs, "fg", label, "store"),
                                         SelectEstimator(runs, "ekf", label, "store"),
                                         Thresholds());
  EXPECT_EQ(reverse.metrics[0].verdict, Verdict::kWorse);
  try {
    SelectEstimator(runs, "factor_graph", label, "out/store.db");
    FAIL() << "an estimator no run has must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("out/store.db"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("it has: ekf, fg"), std::string::npos) << e.what();
  }
}

TEST(RegressionThresholds, TheCheckedInFileLoadsAndBadFilesNameTheirLine) {
  const RegressionThresholds t = LoadRegressionThresholds("scenarios/regression/thresholds.yaml");
  EXPECT_GE(t.metrics.size(), 5u);
  const auto file = std::filesystem::temp_directory_path() /
                    ("thresholds_test_" + std::to_string(getpid()) + ".yaml");
  std::ofstream(file) << "metrics:\n  rmse.x_m: {better: smaller}\n";
  try {
    LoadRegressionThresholds(file);
    ADD_FAILURE() << "accepted 'better: smaller'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":2:"), std::string::npos) << e.what();
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace statebench::reports
