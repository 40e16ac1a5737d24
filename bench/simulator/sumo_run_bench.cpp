// SUMO side of truth generation: 10 minutes of urban driving in a 6 x 6 grid town with traffic
// lights and about 100 traffic vehicles at a time, recorded at 10 Hz (ego reference, driven
// path, every traffic box). Network building (netgenerate, a subprocess) is timed separately.
#include <benchmark/benchmark.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "simulator/sumo_run.hpp"

namespace statebench::sim {
namespace {

const char* kScenario = R"(name: bench_urban_10min
seed: 42
duration_s: 600.0
origin: {latitude_deg: 48.78, longitude_deg: 2.13, altitude_m: 100.0}
vehicle: VEHICLE
network:
  generate:
    grid: {number: 6, x_length_m: 120.0, y_length_m: 100.0, attach_length_m: 60.0}
    speed_mps: 13.89
    traffic_lights: true
    tls_cycle_s: 60
    elevation: {sigma_m: 1.2, limit_m: 2.5}
ego:
  route: [B1B2, B2B3, B3B4, B4C4, C4D4, D4E4, E4E3, E3E2, E2E1, E1D1, D1C1, C1B1]
  loops: 10
traffic:
  density: 100
sumo: {step_s: 0.1}
)";

struct BenchScenario {
  std::filesystem::path dir;
  Scenario scenario;
};

BenchScenario MakeScenario() {
  std::string pattern =
      (std::filesystem::temp_directory_path() / "statebench_sumo_bench_XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  BenchScenario b;
  b.dir = pattern;
  // The vehicle file from the source tree: run from the repository or a build folder inside it
  // (or set STATEBENCH_SOURCE_DIR).
  const auto vehicle = FindVehicleFile(std::filesystem::current_path(), "quadricycle");
  if (!vehicle) throw std::runtime_error("scenarios/vehicles/quadricycle.yaml not found");
  std::string text = kScenario;
  text.replace(text.find("VEHICLE"), 7, vehicle->string());
  std::ofstream(b.dir / "urban.yaml") << text;
  b.scenario = LoadScenario(b.dir / "urban.yaml");
  return b;
}

void BM_BuildNetwork(benchmark::State& state) {
  const BenchScenario b = MakeScenario();
  for (auto _ : state) {
    benchmark::DoNotOptimize(NetworkBuilder().Build(b.scenario, EgoVehicleType(), b.dir / "net"));
  }
  std::filesystem::remove_all(b.dir);
}

// Argument 1: record every traffic box (the lidar world needs them); 0: ego only.
void BM_SumoRun10MinUrban100Vehicles(benchmark::State& state) {
  const BenchScenario b = MakeScenario();
  const BuiltNetwork built = NetworkBuilder().Build(b.scenario, EgoVehicleType(), b.dir / "net");
  SumoRunOptions options;
  options.record_traffic = state.range(0) != 0;
  double boxes = 0.0;
  double frames = 0.0;
  double driven_m = 0.0;
  double samples = 0.0;
  for (auto _ : state) {
    const SumoResult result = RunSumo(b.scenario, built, options);
    for (const TrafficFrame& f : result.traffic) boxes += static_cast<double>(f.boxes.size());
    frames += static_cast<double>(result.traffic.size());
    samples = static_cast<double>(result.ego.size());
    driven_m = result.ego.empty() ? 0.0 : result.ego.back().s_m;
  }
  state.counters["vehicles_at_a_time"] = frames > 0 ? boxes / frames : 0.0;
  state.counters["ego_samples"] = samples;
  state.counters["ego_driven_m"] = driven_m;
  std::filesystem::remove_all(b.dir);
}

BENCHMARK(BM_BuildNetwork)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_SumoRun10MinUrban100Vehicles)
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

}  // namespace
}  // namespace statebench::sim
