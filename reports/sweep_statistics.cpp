#include "reports/sweep_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>

namespace statebench::reports {
namespace {

// Regularised lower incomplete gamma P(a, x): series below a + 1, continued fraction above.
double RegularizedGammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 100000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return sum * std::exp(log_prefix);
  }
  // Lentz's method for the continued fraction of Q(a, x).
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return 1.0 - std::exp(log_prefix) * h;
}

}  // namespace

double SortedQuantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return std::nan("");
  const double pos = q * static_cast<double>(sorted.size() - 1);
  const auto i = static_cast<std::size_t>(std::floor(pos));
  const double f = pos - static_cast<double>(i);
  return i + 1 < sorted.size() ? sorted[i] + f * (sorted[i + 1] - sorted[i]) : sorted[i];
}

double Median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Interval BootstrapInterval(const std::vector<double>& values,
                           const std::function<double(const std::vector<double>&)>& statistic,
                           std::uint64_t seed, int resamples) {
  if (values.empty()) return {std::nan(""), std::nan("")};
  std::mt19937_64 rng(seed);
  std::vector<double> statistics(static_cast<std::size_t>(std::max(resamples, 1)));
  std::vector<double> sample(values.size());
  for (double& t : statistics) {
    for (double& x : sample) x = values[rng() % values.size()];
    t = statistic(sample);
  }
  std::sort(statistics.begin(), statistics.end());
  return {SortedQuantile(statistics, 0.025), SortedQuantile(statistics, 0.975)};
}

MetricSummary Summarize(const std::vector<double>& values, std::uint64_t bootstrap_seed,
                        int bootstrap_resamples) {
  std::vector<double> v;
  for (const double x : values) {
    if (std::isfinite(x)) v.push_back(x);
  }
  MetricSummary s;
  s.count = v.size();
  if (v.empty()) {
    const double nan = std::nan("");
    s.mean = s.median = s.p95 = s.max = s.mean_ci_low = s.mean_ci_high = nan;
    return s;
  }
  std::sort(v.begin(), v.end());
  s.mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  s.median = SortedQuantile(v, 0.5);
  s.p95 = SortedQuantile(v, 0.95);
  s.max = v.back();
  const Interval ci = BootstrapInterval(
      v,
      [](const std::vector<double>& sample) {
        return std::accumulate(sample.begin(), sample.end(), 0.0) /
               static_cast<double>(sample.size());
      },
      bootstrap_seed, bootstrap_resamples);
  s.mean_ci_low = ci.low;
  s.mean_ci_high = ci.high;
  return s;
}

double ChiSquareQuantile(double p, double dof) {
  if (!(dof > 0.0) || !(p > 0.0 && p < 1.0)) {
    throw std::invalid_argument("ChiSquareQuantile: need dof > 0 and 0 < p < 1");
  }
  const double a = dof / 2.0;
  double lo = 0.0, hi = std::max(1.0, dof);
  while (RegularizedGammaP(a, hi / 2.0) < p) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (RegularizedGammaP(a, mid / 2.0) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

ChiSquareBounds AverageNeesBounds(std::size_t runs, double dof, double confidence) {
  if (runs == 0) return {std::nan(""), std::nan("")};
  const double n = static_cast<double>(runs);
  const double alpha = 1.0 - confidence;
  return {ChiSquareQuantile(alpha / 2.0, n * dof) / n,
          ChiSquareQuantile(1.0 - alpha / 2.0, n * dof) / n};
}

}  // namespace statebench::reports
