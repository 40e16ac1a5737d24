#include "reports/sweep_statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace statebench::reports {
namespace {

// Reference quantiles from published chi-square tables.
TEST(ChiSquareQuantile, MatchesTables) {
  EXPECT_NEAR(ChiSquareQuantile(0.975, 1.0), 5.0239, 1e-4);
  EXPECT_NEAR(ChiSquareQuantile(0.95, 6.0), 12.5916, 1e-4);
  EXPECT_NEAR(ChiSquareQuantile(0.025, 6.0), 1.2373, 1e-4);
  EXPECT_NEAR(ChiSquareQuantile(0.5, 2.0), 2.0 * std::log(2.0), 1e-9);
  EXPECT_NEAR(ChiSquareQuantile(0.025, 120.0), 91.5726, 1e-3);
  EXPECT_NEAR(ChiSquareQuantile(0.975, 120.0), 152.2114, 1e-3);
}

// REFERENCE.md: 20 runs of a 6-dof NEES, 95 %: [4.58, 7.61].
TEST(AverageNeesBounds, TwentyRunsOfSixDof) {
  const ChiSquareBounds b = AverageNeesBounds(20, 6.0);
  EXPECT_NEAR(b.low, 4.58, 0.005);
  EXPECT_NEAR(b.high, 7.61, 0.005);
  const ChiSquareBounds one = AverageNeesBounds(1, 6.0);
  EXPECT_NEAR(one.low, 1.2373, 1e-4);
  EXPECT_NEAR(one.high, 14.4494, 1e-3);
}

TEST(Summarize, MomentsQuantilesAndSeededBootstrap) {
  std::vector<double> v;
  for (int i = 1; i <= 100; ++i) v.push_back(i);
  v.push_back(std::nan(""));
  const MetricSummary s = Summarize(v);
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.mean, 50.5);
  EXPECT_DOUBLE_EQ(s.median, 50.5);
  EXPECT_NEAR(s.p95, 95.05, 1e-12);
  EXPECT_DOUBLE_EQ(s.max, 100.0);
  // The mean's standard error is 29.0 / 10 = 2.9: the interval is about +-1.96 * 2.9 wide.
  EXPECT_LT(s.mean_ci_low, s.mean);
  EXPECT_GT(s.mean_ci_high, s.mean);
  EXPECT_NEAR(s.mean_ci_high - s.mean_ci_low, 2.0 * 1.96 * 2.9, 2.0);
  const MetricSummary again = Summarize(v);
  EXPECT_EQ(again.mean_ci_low, s.mean_ci_low);
  EXPECT_EQ(again.mean_ci_high, s.mean_ci_high);
}

TEST(Summarize, EmptyGivesNaN) {
  const MetricSummary s = Summarize({std::nan("")});
  EXPECT_EQ(s.count, 0u);
  EXPECT_TRUE(std::isnan(s.mean));
}

}  // namespace
}  // namespace statebench::reports
