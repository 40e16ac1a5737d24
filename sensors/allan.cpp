#include "sensors/allan.hpp"

#include <cmath>
#include <numeric>

namespace statebench::sensors {

std::vector<AllanPoint> OverlappingAllanDeviation(std::span<const double> samples, double dt_s,
                                                  std::span<const int> cluster_sizes) {
  const std::size_t n = samples.size();
  // Remove the mean first: it does not change the deviation and keeps theta small.
  const double mean = n > 0 ? std::accumulate(samples.begin(), samples.end(), 0.0) / n : 0.0;
  std::vector<double> theta(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) theta[i + 1] = theta[i] + (samples[i] - mean) * dt_s;

  std::vector<AllanPoint> out;
  for (const int m_int : cluster_sizes) {
    const auto m = static_cast<std::size_t>(m_int);
    if (m_int < 1 || 2 * m >= n + 1) continue;
    const std::size_t terms = n + 1 - 2 * m;
    double sum = 0.0;
    for (std::size_t k = 0; k < terms; ++k) {
      const double d = theta[k + 2 * m] - 2.0 * theta[k + m] + theta[k];
      sum += d * d;
    }
    const double tau = static_cast<double>(m) * dt_s;
    out.push_back({tau, std::sqrt(sum / (2.0 * tau * tau * static_cast<double>(terms)))});
  }
  return out;
}

NoiseFit FitWhiteNoiseAndRandomWalk(const std::vector<AllanPoint>& curve, double white_tau_max_s,
                                    double rw_tau_max_s) {
  NoiseFit fit;
  double log_n = 0.0;
  for (const AllanPoint& p : curve) {
    if (p.tau_s > white_tau_max_s) continue;
    log_n += std::log(p.deviation) + 0.5 * std::log(p.tau_s);  // log N at tau = 1 s
    ++fit.white_points;
  }
  if (fit.white_points == 0) return fit;
  fit.noise_density = std::exp(log_n / fit.white_points);

  // Weighted sums for the fixed-slope intercept and the free slope of log r over log tau.
  double sw = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, s_log_k = 0.0;
  for (const AllanPoint& p : curve) {
    const double white_var = fit.noise_density * fit.noise_density / p.tau_s;
    const double rw_var = p.deviation * p.deviation - white_var;
    if (rw_var <= white_var || p.tau_s > rw_tau_max_s) continue;
    const double w = 1.0 / p.tau_s;
    const double x = std::log(p.tau_s);
    const double y = 0.5 * std::log(rw_var);
    s_log_k += w * (y - 0.5 * std::log(p.tau_s / 3.0));
    sw += w;
    sx += w * x;
    sy += w * y;
    sxx += w * x * x;
    sxy += w * x * y;
    ++fit.rw_points;
  }
  if (fit.rw_points == 0) return fit;
  fit.random_walk = std::exp(s_log_k / sw);
  const double denom = sw * sxx - sx * sx;
  fit.rw_slope = denom > 0.0 ? (sw * sxy - sx * sy) / denom : 0.0;
  return fit;
}

std::vector<int> LogSpacedClusterSizes(int max_size, int per_decade) {
  std::vector<int> sizes;
  for (int i = 0;; ++i) {
    const int m =
        static_cast<int>(std::lround(std::pow(10.0, static_cast<double>(i) / per_decade)));
    if (m > max_size) break;
    if (sizes.empty() || m > sizes.back()) sizes.push_back(m);
  }
  return sizes;
}

}  // namespace statebench::sensors
