// statebench record SCENARIO.yaml --out LOG [--seed N] [--duration S] [--lidar-format F] [--quiet]
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/progress_bar.hpp"
#include "apps/scenario_overrides.hpp"
#include "core/error.hpp"
#include "sensors/lidar_sensor_model.hpp"
#include "sensors/log_format.hpp"
#include "sensors/log_writer.hpp"
#include "simulator/scenario.hpp"
#include "simulator/sensor_run.hpp"

namespace statebench::app {
namespace {

constexpr const char* kUsage =
    "usage: statebench record SCENARIO.yaml --out LOG [--seed N] [--duration S]\n"
    "                         [--lidar-format packets|sweep|pcd] [--quiet]\n"
    "  Simulates the scenario's truth and every sensor of its setup (`sensors:` in the scenario,\n"
    "  with its `faults:`) and writes a recorded log directory (docs/log-format.md): IMU, GNSS,\n"
    "  encoder CSVs, one file per lidar sweep, setup.yaml, truth.csv + TUM, log.yaml.\n"
    "  --seed N      scenario seed (traffic, world, sensor errors)\n"
    "  --duration S  simulated seconds (default: the scenario's)\n"
    "  --lidar-format packets|sweep|pcd  packets (default): what the lidar's packets carry\n"
    "                (beam model, a range and an intensity byte per return), about 4x smaller\n"
    "                than PCDs and faster to read; sweep: compressed StateBench sweep files,\n"
    "                about 5x smaller, 5x slower to read; pcd: binary PCDs, for PCL tools.\n"
    "                All three lossless\n";

// GNSS fix counts by status, for the summary ("rtk_fixed 2391, rtk_float 9").
std::string StatusCounts(const std::map<GnssFixStatus, std::size_t>& counts) {
  std::string out;
  for (const auto& [status, n] : counts) {
    if (!out.empty()) out += ", ";
    out += std::string(sensors::GnssStatusName(status)) + " " + std::to_string(n);
  }
  return out;
}

}  // namespace

int RunRecord(const std::vector<std::string>& argv) {
  const auto parsed =
      ParseCommand({"record", kUsage, {"quiet"}, {"out", "seed", "duration", "lidar-format"}, 1, {"out"}}, argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs* args = &std::get<CliArgs>(parsed);
  const std::filesystem::path out_dir = *args->Option("out");
  const bool quiet = args->Flag("quiet");
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    const sim::Scenario scenario = LoadScenarioWithOverrides(*args);
    sensors::LidarFileFormat lidar_format = sensors::LidarFileFormat::kPackets;
    if (const auto name = args->Option("lidar-format")) {
      const auto parsed_format = sensors::ParseLidarFileFormat(*name);
      if (!parsed_format) {
        throw InputError("--lidar-format: '" + *name + "' is not packets, sweep or pcd");
      }
      lidar_format = *parsed_format;
    }
    if (std::filesystem::exists(out_dir / "log.yaml")) {
      throw InputError(out_dir.string() + ": already holds a log (log.yaml); remove it or " +
                       "choose another --out");
    }

    if (!quiet) {
      std::fprintf(stderr, "record: %s: building network, running SUMO, building the world...\n",
                   scenario.name.c_str());
    }
    sim::SensorRun run(scenario, out_dir);
    sensors::LogWriterOptions options;
    options.scenario = scenario.name;
    options.seed = scenario.seed;
    options.origin = scenario.origin;
    options.setup_yaml = run.sensors().setup_yaml;
    options.truth_T_body_imu = run.T_body_imu();
    options.lidar_format = lidar_format;
    for (const sensors::SensorConfig* lidar :
         run.sensors().setup.OfType(sensors::SensorType::kLidar)) {
      options.lidar_beams[lidar->spec.id] =
          sensors::LidarParamsFromSetup(lidar->spec, std::get<sensors::LidarOptions>(lidar->options),
                                        lidar->where)
              .beams;
    }
    sensors::LogWriter writer(out_dir, options);

    ProgressBar bar("record " + scenario.name);
    const double end_s = ToSeconds(run.truth().end_ns());
    double t_s = 0.0;
    const auto synthesis_start = std::chrono::steady_clock::now();
    run.SetTruthObserver([&](const TruthSample& sample) {
      writer.WriteTruth(sample);
      t_s = ToSeconds(sample.t_ns);
      if (!quiet && sample.t_ns % (100 * kNsPerMillisecond) == 0) {
        char detail[64];
        std::snprintf(detail, sizeof(detail), "t=%.1f s  %.0f m", t_s, sample.distance_m);
        bar.Update(t_s / end_s, detail);
      }
    });
    std::map<std::string, std::map<GnssFixStatus, std::size_t>> gnss_status;
    while (std::optional<Measurement> m = run.Next()) {
      if (const auto* fix = std::get_if<GnssFix>(&*m)) {
        ++gnss_status[fix->header.sensor_id][fix->status];
      }
      writer.Write(*m);
    }
    writer.Close();
    if (!quiet) bar.Finish();

    const auto now = std::chrono::steady_clock::now();
    const double wall_s = std::chrono::duration<double>(now - wall_start).count();
    const double synthesis_s = std::chrono::duration<double>(now - synthesis_start).count();
    std::printf("%s (seed %llu, setup %s): %.1f s simulated -> %s\n", scenario.name.c_str(),
                static_cast<unsigned long long>(scenario.seed), run.sensors().setup.name.c_str(),
                t_s, out_dir.string().c_str());
    for (const sensors::LogStreamStats& s : writer.stats()) {
      std::printf("  %-14s %-20s %8zu", s.id.c_str(),
                  std::string(sensors::LogStreamTypeName(s.type)).c_str(), s.count);
      if (s.type == sensors::LogStreamType::kLidar) {
        std::printf("  (%zu points, %.0f per sweep)", s.lidar_points,
                    s.count ? static_cast<double>(s.lidar_points) / s.count : 0.0);
      }
      if (const auto it = gnss_status.find(s.id); it != gnss_status.end()) {
        std::printf("  (%s)", StatusCounts(it->second).c_str());
      }
      std::printf("\n");
    }
    std::printf("wall %.1f s (%.1f s for truth + sensors + writing: %.1fx real time)\n", wall_s,
                synthesis_s, synthesis_s > 0 ? t_s / synthesis_s : 0.0);
    return 0;
  } catch (...) {
    return ExitCodeForCurrentException("record");
  }
}

}  // namespace statebench::app
