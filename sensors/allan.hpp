// Overlapping Allan deviation (IEEE Std 952) of a rate signal sampled at period dt:
//
//   theta_k = dt * sum_{i<k} y_i,  k = 0..N   (integrated signal of N samples),  tau = m dt,
//   sigma^2(tau) = sum_{k=0}^{N-2m} (theta_{k+2m} - 2 theta_{k+m} + theta_k)^2
//                  / (2 tau^2 (N + 1 - 2m))
//
// For white noise of density N (unit/sqrt(Hz)) sigma(tau) = N / sqrt(tau), so sigma(1 s) = N;
// for a bias random walk of density K, sigma(tau) = K sqrt(tau / 3), so the +1/2 slope line
// passes through K at tau = 3 s.
#pragma once

#include <span>
#include <vector>

namespace statebench::sensors {

struct AllanPoint {
  double tau_s = 0.0;
  double deviation = 0.0;
};

// One point per cluster size m (1 <= m < N/2); other sizes are skipped.
std::vector<AllanPoint> OverlappingAllanDeviation(std::span<const double> samples, double dt_s,
                                                  std::span<const int> cluster_sizes);

// Reading a white-noise density N and a bias random walk K off an Allan curve:
//  - N: the line of slope -1/2 fitted (in log-log, equal weights) to the points with
//    tau <= white_tau_max_s, evaluated at tau = 1 s. Below the crossover tau_c = sqrt(3) N / K
//    white noise dominates; white_tau_max_s must be well below it (0.1 s suits MEMS IMUs).
//  - K: the white part N^2 / tau is subtracted from sigma^2, the line of slope +1/2 is fitted to
//    the remainder where it dominates (remainder > N^2 / tau, i.e. tau > tau_c) up to
//    rw_tau_max_s, each point weighted by 1 / tau (~ its number of independent clusters), and
//    evaluated at tau = 3 s. rw_slope is the free log-log slope of the remainder over the same
//    points (+1/2 for a random walk).
struct NoiseFit {
  double noise_density = 0.0;
  double random_walk = 0.0;
  double rw_slope = 0.0;
  int white_points = 0;
  int rw_points = 0;
};
NoiseFit FitWhiteNoiseAndRandomWalk(const std::vector<AllanPoint>& curve, double white_tau_max_s,
                                    double rw_tau_max_s);

// Cluster sizes spaced logarithmically, `per_decade` per decade, from 1 to max_size.
std::vector<int> LogSpacedClusterSizes(int max_size, int per_decade);

}  // namespace statebench::sensors
