#include "core/running_statistics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <vector>

namespace statebench {
namespace {

double ExactQuantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

double ExactMedian(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

TEST(RunningStatistics, MomentsExactAndQuantilesWithinTheirResolution) {
  std::mt19937_64 rng(17);
  std::lognormal_distribution<double> dist(-1.0, 1.5);  // 1 mm .. 100 m, a long tail
  for (const std::size_t n : {1u, 2u, 3u, 10u, 1001u, 20000u}) {
    std::vector<double> v(n);
    RunningStatistics s;
    for (double& x : v) {
      x = dist(rng);
      s.Add(x);
    }
    const double mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(n);
    double var = 0.0, sq = 0.0;
    for (const double x : v) {
      var += (x - mean) * (x - mean);
      sq += x * x;
    }
    SCOPED_TRACE(n);
    EXPECT_EQ(s.count(), n);
    EXPECT_NEAR(s.mean(), mean, 1e-12 * mean);
    EXPECT_NEAR(s.rms(), std::sqrt(sq / static_cast<double>(n)), 1e-12 * mean);
    EXPECT_NEAR(s.std(), std::sqrt(var / static_cast<double>(n)), 1e-9 * mean);
    EXPECT_EQ(s.max(), *std::max_element(v.begin(), v.end()));
    EXPECT_EQ(s.min(), *std::min_element(v.begin(), v.end()));
    const double r = RunningStatistics::kRelativeResolution;
    const double median = ExactMedian(v);
    EXPECT_NEAR(s.Median(), median, r * median);
    for (const double q : {0.0, 0.05, 0.5, 0.95, 0.99, 1.0}) {
      const double exact = ExactQuantile(v, q);
      EXPECT_NEAR(s.Quantile(q), exact, r * exact) << "q " << q;
    }
  }
}

TEST(RunningStatistics, EmptyZerosAndHugeValues) {
  RunningStatistics s;
  EXPECT_EQ(s.Median(), 0.0);
  EXPECT_EQ(s.max(), 0.0);
  EXPECT_EQ(s.rms(), 0.0);
  s.Add(0.0);
  s.Add(0.0);
  EXPECT_EQ(s.Median(), 0.0);  // clamped to the exact minimum
  s.Add(1e12);                 // beyond the last bin: the exact maximum is still known
  EXPECT_EQ(s.max(), 1e12);
  EXPECT_EQ(s.Quantile(1.0), 1e12);
  EXPECT_EQ(s.Median(), 0.0);
}

TEST(RunningStatistics, LogHistogramCountsEveryValueInItsDecadeBin) {
  RunningStatistics s;
  EXPECT_TRUE(s.LogHistogram(10).empty());
  // Values away from the bin edges (closer than the 0.1 % resolution a value may fall either
  // side): bin k of 4 per decade is [10^(k/4), 10^((k+1)/4)).
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> inside(0.02, 0.98);
  std::uniform_int_distribution<int> bin(-6, 9);  // 0.03 .. 178
  std::map<int, std::uint64_t> expected;
  for (int i = 0; i < 5000; ++i) {
    const int k = bin(rng);
    if (k == 2) continue;  // an empty bin between non-empty ones
    s.Add(std::pow(10.0, (k + inside(rng)) / 4.0));
    ++expected[k];
  }
  const std::vector<RunningStatistics::LogBin> h = s.LogHistogram(4);
  ASSERT_EQ(h.size(), 16u);
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const int k = -6 + static_cast<int>(i);
    EXPECT_NEAR(h[i].low, std::pow(10.0, k / 4.0), 1e-12 * h[i].high) << k;
    EXPECT_NEAR(h[i].high, std::pow(10.0, (k + 1) / 4.0), 1e-12 * h[i].high) << k;
    EXPECT_EQ(h[i].count, expected[k]) << k;
    total += h[i].count;
  }
  EXPECT_EQ(h[8].count, 0u);
  EXPECT_EQ(total, s.count());
}

}  // namespace
}  // namespace statebench
