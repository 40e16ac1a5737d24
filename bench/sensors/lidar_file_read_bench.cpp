// Reading lidar sweeps back (lidar_file.hpp), CPU time per sweep (the file read from the page
// cache, decoded into points):
//   BM_ReadPcd, BM_ReadSweepFile, BM_ReadPacketsFile  the same sweeps in each format: every 10th
//       sweep of the log's first lidar, rewritten into the three formats in a temporary directory
//       removed at exit (the packets files with the lidar's beam model from the log's setup.yaml);
//   BM_ReadLogSweeps  every sweep file of the log as recorded, whatever its format: one
//       iteration reads them all (its CPU time is the log's reading cost).
//
// Run: STATEBENCH_BENCH_LOG=LOG build/bin/lidar_file_read_bench
//      (LOG from `statebench record scenarios/paper/setup2_quadricycle.yaml --out LOG --duration 24`)
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sensors/lidar_file.hpp"
#include "sensors/lidar_sensor_model.hpp"
#include "sensors/sensor_setup.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;

constexpr std::array<LidarFileFormat, 3> kFormats = {LidarFileFormat::kPcd, LidarFileFormat::kSweep,
                                                     LidarFileFormat::kPackets};

struct SweepSet {
  fs::path dir;
  std::vector<fs::path> recorded;                        // every sweep file of the first lidar
  std::array<std::vector<fs::path>, kFormats.size()> files;  // by kFormats
  std::array<std::uintmax_t, kFormats.size()> bytes{};
  std::size_t points = 0;
  ~SweepSet() {
    std::error_code ec;
    if (!dir.empty()) fs::remove_all(dir, ec);
  }
};

// The beam model of lidar `id` in the log's setup.yaml.
std::optional<LidarBeamModel> BeamsOf(const fs::path& log, const std::string& id) {
  const SensorSetup setup = LoadSensorSetup(log / "setup.yaml");
  const SensorConfig* lidar = setup.Find(id);
  if (lidar == nullptr || lidar->type() != SensorType::kLidar) return std::nullopt;
  return LidarParamsFromSetup(lidar->spec, std::get<LidarOptions>(lidar->options), lidar->where)
      .beams;
}

const SweepSet& Sweeps() {
  static SweepSet set = [] {
    SweepSet s;
    const char* log = std::getenv("STATEBENCH_BENCH_LOG");
    if (log == nullptr) return s;
    std::string id;
    for (const auto& lidar : fs::directory_iterator(fs::path(log) / "lidar")) {
      if (!lidar.is_directory()) continue;
      id = lidar.path().filename().string();
      for (const auto& f : fs::directory_iterator(lidar.path())) s.recorded.push_back(f.path());
      break;
    }
    std::sort(s.recorded.begin(), s.recorded.end());
    const std::optional<LidarBeamModel> beams = BeamsOf(log, id);
    s.dir = fs::temp_directory_path() / ("lidar_file_read_bench_" + std::to_string(::getpid()));
    fs::create_directories(s.dir);
    for (std::size_t i = 0; i < s.recorded.size(); i += 10) {
      const std::vector<LidarPoint> points = ReadLidarFile(s.recorded[i]);
      s.points += points.size();
      for (std::size_t f = 0; f < kFormats.size(); ++f) {
        const std::string name = WriteLidarFile(s.dir, std::to_string(i), points, kFormats[f],
                                                beams ? &*beams : nullptr);
        s.files[f].push_back(s.dir / name);
        s.bytes[f] += fs::file_size(s.dir / name);
      }
    }
    return s;
  }();
  return set;
}

void ReadSweeps(benchmark::State& state, std::size_t format) {
  const SweepSet& s = Sweeps();
  if (s.recorded.empty()) {
    state.SkipWithError("set STATEBENCH_BENCH_LOG to a recorded log with a lidar");
    return;
  }
  const std::vector<fs::path>& files = s.files[format];
  std::size_t n = 0;
  for (auto _ : state) {
    const std::vector<LidarPoint> points = ReadLidarFile(files[n++ % files.size()]);
    benchmark::DoNotOptimize(points.data());
  }
  state.counters["points_per_sweep"] = static_cast<double>(s.points) / files.size();
  state.counters["bytes_per_sweep"] = static_cast<double>(s.bytes[format]) / files.size();
}

void BM_ReadPcd(benchmark::State& state) { ReadSweeps(state, 0); }
void BM_ReadSweepFile(benchmark::State& state) { ReadSweeps(state, 1); }
void BM_ReadPacketsFile(benchmark::State& state) { ReadSweeps(state, 2); }
BENCHMARK(BM_ReadPcd)->MeasureProcessCPUTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReadSweepFile)->MeasureProcessCPUTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReadPacketsFile)->MeasureProcessCPUTime()->Unit(benchmark::kMicrosecond);

void BM_ReadLogSweeps(benchmark::State& state) {
  const SweepSet& s = Sweeps();
  if (s.recorded.empty()) {
    state.SkipWithError("set STATEBENCH_BENCH_LOG to a recorded log with a lidar");
    return;
  }
  std::size_t points = 0;
  for (auto _ : state) {
    points = 0;
    for (const fs::path& file : s.recorded) points += ReadLidarFile(file).size();
    benchmark::DoNotOptimize(points);
  }
  state.counters["sweeps"] = static_cast<double>(s.recorded.size());
  state.counters["points"] = static_cast<double>(points);
}
BENCHMARK(BM_ReadLogSweeps)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace statebench::sensors

BENCHMARK_MAIN();
