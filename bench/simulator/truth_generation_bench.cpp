// Truth generation end to end: 10 minutes of urban driving with ~100 traffic vehicles at a time
// (scenarios/bench/urban_10min.yaml): network build, SUMO run, terrain and path fit, and the
// 1 kHz vehicle model producing 600k truth samples (not written to disk). Single-threaded.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "simulator/truth_simulation.hpp"

namespace statebench::sim {
namespace {

std::filesystem::path SourceDir() {
  const char* dir = std::getenv("STATEBENCH_SOURCE_DIR");
  if (dir) return dir;
  // Run from the repository or from a build folder inside it.
  for (auto p = std::filesystem::current_path(); !p.empty(); p = p.parent_path()) {
    if (std::filesystem::exists(p / "scenarios/bench/urban_10min.yaml")) return p;
    if (p == p.parent_path()) break;
  }
  return std::filesystem::current_path();
}

void BM_TruthUrban10min(benchmark::State& state) {
  const Scenario scenario = LoadScenario(SourceDir() / "scenarios/bench/urban_10min.yaml");
  const auto work = std::filesystem::temp_directory_path() / "statebench_truth_bench";
  double simulated_s = 0.0;
  int traffic = 0;
  for (auto _ : state) {
    TruthSimulation sim(scenario, work);
    TruthSample s;
    while (sim.Next(&s)) benchmark::DoNotOptimize(s);
    simulated_s = sim.summary().duration_s;
    traffic = sim.summary().max_traffic_vehicles;
  }
  state.counters["simulated_s"] = simulated_s;
  state.counters["max_traffic"] = traffic;
  state.counters["real_time_factor"] = benchmark::Counter(
      simulated_s * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TruthUrban10min)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace statebench::sim
