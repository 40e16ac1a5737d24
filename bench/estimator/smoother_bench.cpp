// Cost of the factor-graph estimator on a 40 s drive (noisy industrial IMU at 100 Hz, one GNSS
// antenna at 10 Hz, the test fixture's figure eight): per update (solve + marginalisation +
// newest covariance, every 0.1 s) the median and 99th percentile, and per IMU sample the cost of
// Add() + StateAt(newest) (the 100 Hz output). Windows 0.5, 1 and 2 s; a state per IMU sample
// (the paper) or keyframes every 10 samples. The RMS position and yaw errors of the IMU-rate
// output after convergence show what keyframes cost in accuracy.
//
// Run: build/bin/smoother_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "estimator/factor_graph_estimator.hpp"
#include "tests/estimator/estimator_scenario.hpp"

namespace statebench::est {
namespace {

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

const testing::Scenario& Drive() {
  static const testing::Scenario sc = testing::MakeScenario(testing::DriftingImuRtkOptions(40.0));
  return sc;
}

// Args: window in ms, IMU samples per state, reorder latency in ms.
void BM_FactorGraphEstimator(benchmark::State& state) {
  const testing::Scenario& sc = Drive();
  FactorGraphOptions options;
  options.origin = testing::kTestOrigin;
  options.window_s = static_cast<double>(state.range(0)) / 1000.0;
  options.imu_samples_per_state = static_cast<int>(state.range(1));
  options.reorder_latency_s = static_cast<double>(state.range(2)) / 1000.0;
  std::vector<double> imu_us;
  UpdateLog updates;
  double sum_p2 = 0.0, sum_yaw2 = 0.0;
  int n_err = 0;
  for (auto _ : state) {
    FactorGraphEstimator estimator(testing::MakeSetup(sc.options), options);
    imu_us.clear();
    sum_p2 = sum_yaw2 = 0.0;
    n_err = 0;
    for (const Measurement& m : sc.stream) {
      const bool is_imu = std::holds_alternative<ImuSample>(m);
      const auto start = std::chrono::steady_clock::now();
      estimator.Add(m);
      const TimeNs t = HeaderOf(m).stamp_ns;
      std::optional<StateEstimate> e;
      if (is_imu) e = estimator.StateAt(t);
      const auto stop = std::chrono::steady_clock::now();
      if (!is_imu) continue;
      imu_us.push_back(std::chrono::duration<double, std::micro>(stop - start).count());
      if (e && ToSeconds(t) > 15.0) {
        const NavState truth = sc.Truth(t);
        sum_p2 += (e->state.p_world - truth.p_world).squaredNorm();
        const double yaw = so3::ToRollPitchYaw(e->state.q_world_imu).z() -
                           so3::ToRollPitchYaw(truth.q_world_imu).z();
        sum_yaw2 += std::pow(so3::WrapAngle(yaw), 2);
        ++n_err;
      }
    }
    updates = estimator.diagnostics().updates;
  }
  state.counters["solve_median_ms"] = updates.solve_ms().Median();
  state.counters["solve_p99_ms"] = updates.solve_ms().Quantile(0.99);
  state.counters["solve_max_ms"] = updates.solve_ms().max();
  // Most IMU samples trigger no solve: the median is the cost of the 100 Hz prediction.
  state.counters["imu_median_us"] = Percentile(imu_us, 0.5);
  state.counters["rms_pos_mm"] = 1e3 * std::sqrt(sum_p2 / std::max(n_err, 1));
  state.counters["rms_yaw_mrad"] = 1e3 * std::sqrt(sum_yaw2 / std::max(n_err, 1));
  state.counters["updates"] = static_cast<double>(updates.count());
}
BENCHMARK(BM_FactorGraphEstimator)
    ->ArgsProduct({{500, 1000, 2000}, {1, 10}, {500}})
    ->Args({1000, 10, 150})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace statebench::est
