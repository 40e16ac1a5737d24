// Sensor synthesis speed of the paper's setup 2 (quadricycle, front GNSS, Hesai XT32 at 10 Hz,
// IMU 100 Hz, steering and speed encoders) through the whole pipeline: 1 kHz truth (vehicle
// model on SUMO's reference) -> every sensor model, the lidar ray cast into the world built from
// the SUMO network with its traffic -> one stream in arrival order. Nothing is written to disk.
// The SUMO run and the world build (once per scenario, shared by Monte Carlo seeds) are outside
// the timing. Reported as simulated seconds per wall second (x_real_time) on 1 and 2 TBB threads.
//
// Run: build-*/bin/sensor_synthesis_bench  (from the repository, or with STATEBENCH_SOURCE_DIR)
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cstdlib>
#include <filesystem>

#include "simulator/sensor_run.hpp"

namespace statebench::sim {
namespace {

constexpr double kSimulatedSeconds = 20.0;

std::filesystem::path SourceDir() {
  if (const char* dir = std::getenv("STATEBENCH_SOURCE_DIR")) return dir;
  for (auto p = std::filesystem::current_path(); !p.empty(); p = p.parent_path()) {
    if (std::filesystem::exists(p / "scenarios/paper/setup2_quadricycle.yaml")) return p;
    if (p == p.parent_path()) break;
  }
  return std::filesystem::current_path();
}

void BM_Setup2Synthesis(benchmark::State& state) {
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(state.range(0)));
  Scenario scenario = LoadScenario(SourceDir() / "scenarios/paper/setup2_quadricycle.yaml");
  scenario.duration_s = kSimulatedSeconds;
  const auto work = std::filesystem::temp_directory_path() / "statebench_synthesis_bench";
  std::size_t measurements = 0, points = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto run = std::make_unique<SensorRun>(scenario, work);  // SUMO + world: not timed
    state.ResumeTiming();
    while (std::optional<Measurement> m = run->Next()) {
      ++measurements;
      if (const auto* scan = std::get_if<LidarScan>(&*m)) points += scan->points->size();
    }
    state.PauseTiming();
    run.reset();
    state.ResumeTiming();
  }
  const double iterations = static_cast<double>(state.iterations());
  state.counters["x_real_time"] =
      benchmark::Counter(kSimulatedSeconds * iterations, benchmark::Counter::kIsRate);
  state.counters["lidar_points_per_s"] =
      benchmark::Counter(static_cast<double>(points), benchmark::Counter::kIsRate);
  state.counters["measurements"] = static_cast<double>(measurements) / iterations;
  std::filesystem::remove_all(work);
}
BENCHMARK(BM_Setup2Synthesis)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Iterations(2)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace
}  // namespace statebench::sim
