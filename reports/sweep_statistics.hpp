// Statistics over the runs of a sweep: the distribution of a metric (mean, median, p95, max and
// a seeded bootstrap interval of the mean) and the chi-square bounds the average NEES over N runs
// must meet (REFERENCE.md: N * ANEES ~ chi2(N * dof) for a consistent estimator).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace statebench::reports {

// Quantile q of sorted values, linear interpolation between order statistics (NaN when empty).
double SortedQuantile(const std::vector<double>& sorted, double q);
// The middle value, or the mean of the two middle values (NaN when empty).
double Median(std::vector<double> values);

struct Interval {
  double low = 0.0;
  double high = 0.0;
};
// 95 % percentile bootstrap interval of statistic(resample): `resamples` resamples with
// replacement drawn from a generator seeded with `seed` (same input, same interval). NaN when
// `values` is empty.
Interval BootstrapInterval(const std::vector<double>& values,
                           const std::function<double(const std::vector<double>&)>& statistic,
                           std::uint64_t seed, int resamples);

struct MetricSummary {
  std::size_t count = 0;  // finite values
  double mean = 0.0;
  double median = 0.0;
  double p95 = 0.0;  // linear interpolation between order statistics
  double max = 0.0;
  double mean_ci_low = 0.0;  // 95 % percentile bootstrap interval of the mean
  double mean_ci_high = 0.0;
};

// Non-finite values are left out (count says how many remained). Same values and seed: same
// interval. An empty input gives count 0 and NaN everywhere.
MetricSummary Summarize(const std::vector<double>& values, std::uint64_t bootstrap_seed = 1,
                        int bootstrap_resamples = 2000);

// Quantile p of the chi-square distribution with `dof` degrees of freedom (dof > 0, 0 < p < 1),
// to 1e-10 relative.
double ChiSquareQuantile(double p, double dof);

struct ChiSquareBounds {
  double low = 0.0;
  double high = 0.0;
};

// Two-sided `confidence` bounds of the average of N independent NEES values of `dof` degrees of
// freedom each: [chi2((1-c)/2, N dof) / N, chi2((1+c)/2, N dof) / N].
ChiSquareBounds AverageNeesBounds(std::size_t runs, double dof, double confidence = 0.95);

}  // namespace statebench::reports
