// Cost of the 1 kHz vehicle simulation alone (no SUMO): one benchmark iteration is 1 s of
// driving (1000 RK4 steps with the path tracker and speed controller inside every stage, plus
// one exact TruthSample per step) on the synthetic urban route with its hilly terrain.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "simulator/synthetic_route.hpp"
#include "simulator/vehicle_simulation.hpp"

namespace statebench::sim {
namespace {

std::filesystem::path VehicleFile(const std::string& name) {
  const char* root = std::getenv("STATEBENCH_SOURCE_DIR");
  for (auto p = std::filesystem::current_path(); !root && !p.empty(); p = p.parent_path()) {
    if (std::filesystem::exists(p / "scenarios/vehicles" / (name + ".yaml"))) {
      return p / "scenarios/vehicles" / (name + ".yaml");
    }
    if (p == p.parent_path()) break;
  }
  return std::filesystem::path(root ? root : ".") / "scenarios/vehicles" / (name + ".yaml");
}

void BM_VehicleSimulationOneSecond(benchmark::State& state, const std::string& vehicle,
                                   bool hilly) {
  const VehicleParams params = LoadVehicleParamsFile(VehicleFile(vehicle));
  SyntheticRouteOptions options;
  options.hilly = hilly;
  options.duration_s = 120.0;
  const SyntheticRoute route = MakeSyntheticRoute(options);
  auto terrain = std::make_shared<const Terrain>(Terrain::FitPolylines(route.network));
  auto path = std::make_shared<const Path>(Path::Build(route.polyline, PathOptionsFor(params)));
  std::vector<ReferenceSample> reference;
  for (int k = 0; k < 120000; ++k) reference.push_back(SampleProfile(route.profile, k * 1e-3));
  VehicleSimulation sim(params, path, terrain);
  sim.Reset(options.start_s_m, 0.0);
  std::size_t k = 0;
  double checksum = 0.0;
  for (auto _ : state) {
    if (k + 1000 > reference.size()) {  // start the route again
      state.PauseTiming();
      sim.Reset(options.start_s_m, 0.0);
      k = 0;
      state.ResumeTiming();
    }
    for (int i = 0; i < 1000; ++i, ++k) {
      sim.Step(reference[k].s_m, reference[k].v_mps, reference[k].a_mps2);
      checksum += sim.Truth().body.a_world.x();
    }
  }
  benchmark::DoNotOptimize(checksum);
  state.counters["steps_per_s"] =
      benchmark::Counter(1000.0 * state.iterations(), benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(BM_VehicleSimulationOneSecond, quadricycle_hilly, "quadricycle", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_VehicleSimulationOneSecond, quadricycle_flat, "quadricycle", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_VehicleSimulationOneSecond, shuttle_hilly, "shuttle", true)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace statebench::sim
