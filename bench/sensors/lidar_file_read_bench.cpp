// Reading lidar sweeps back: a binary PCD against a StateBench sweep file (lidar_file.hpp), the
// same sweeps in both formats, CPU time per sweep (the file read from the page cache, decoded into
// points). The sweeps come from a recorded log (every 10th sweep of its first lidar), rewritten
// into both formats in a temporary directory removed at exit.
//
// Run: STATEBENCH_BENCH_LOG=LOG build/bin/lidar_file_read_bench
//      (LOG from `statebench record scenarios/paper/setup2_quadricycle.yaml --out LOG --duration 24`)
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "sensors/lidar_file.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;

struct SweepSet {
  fs::path dir;
  std::vector<fs::path> pcd, sweep;
  std::size_t points = 0;
  std::uintmax_t pcd_bytes = 0, sweep_bytes = 0;
  ~SweepSet() {
    std::error_code ec;
    if (!dir.empty()) fs::remove_all(dir, ec);
  }
};

const SweepSet& Sweeps() {
  static SweepSet set = [] {
    SweepSet s;
    const char* log = std::getenv("STATEBENCH_BENCH_LOG");
    if (log == nullptr) return s;
    std::vector<fs::path> files;
    for (const auto& lidar : fs::directory_iterator(fs::path(log) / "lidar")) {
      if (!lidar.is_directory()) continue;
      for (const auto& f : fs::directory_iterator(lidar.path())) files.push_back(f.path());
      break;
    }
    std::sort(files.begin(), files.end());
    s.dir = fs::temp_directory_path() / ("lidar_file_read_bench_" + std::to_string(::getpid()));
    fs::create_directories(s.dir);
    for (std::size_t i = 0; i < files.size(); i += 10) {
      const std::vector<LidarPoint> points = ReadLidarFile(files[i]);
      s.points += points.size();
      for (const LidarFileFormat format : {LidarFileFormat::kPcd, LidarFileFormat::kSweep}) {
        const fs::path out = s.dir / (std::to_string(i) + std::string(LidarFileExtension(format)));
        WriteLidarFile(out, points, format);
        (format == LidarFileFormat::kPcd ? s.pcd : s.sweep).push_back(out);
        (format == LidarFileFormat::kPcd ? s.pcd_bytes : s.sweep_bytes) += fs::file_size(out);
      }
    }
    return s;
  }();
  return set;
}

void ReadSweeps(benchmark::State& state, bool sweep_files) {
  const SweepSet& s = Sweeps();
  if (s.pcd.empty()) {
    state.SkipWithError("set STATEBENCH_BENCH_LOG to a recorded log with a lidar");
    return;
  }
  const std::vector<fs::path>& files = sweep_files ? s.sweep : s.pcd;
  std::size_t n = 0;
  for (auto _ : state) {
    const std::vector<LidarPoint> points = ReadLidarFile(files[n++ % files.size()]);
    benchmark::DoNotOptimize(points.data());
  }
  state.counters["points_per_sweep"] = static_cast<double>(s.points) / s.pcd.size();
  state.counters["bytes_per_sweep"] =
      static_cast<double>(sweep_files ? s.sweep_bytes : s.pcd_bytes) / s.pcd.size();
}

void BM_ReadPcd(benchmark::State& state) { ReadSweeps(state, false); }
void BM_ReadSweepFile(benchmark::State& state) { ReadSweeps(state, true); }
BENCHMARK(BM_ReadPcd)->MeasureProcessCPUTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReadSweepFile)->MeasureProcessCPUTime()->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace statebench::sensors

BENCHMARK_MAIN();
