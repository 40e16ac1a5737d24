// statebench simulate SCENARIO.yaml --out DIR [--seed N] [--duration S] [--quiet]
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/progress_bar.hpp"
#include "apps/scenario_overrides.hpp"
#include "core/error.hpp"
#include "core/truth_io.hpp"
#include "simulator/scenario.hpp"
#include "simulator/truth_simulation.hpp"

namespace statebench::app {
namespace {

constexpr const char* kUsage =
    "usage: statebench simulate SCENARIO.yaml --out DIR [--seed N] [--duration S] [--quiet]\n"
    "  Runs the scenario's SUMO traffic and the ego vehicle model and writes exact truth at\n"
    "  1 kHz (truth.csv, truth_body.tum, truth_imu.tum), traffic.csv, path.csv, summary.json.\n";

nlohmann::json SummaryJson(const sim::TruthSummary& s, double wall_s) {
  return {{"scenario", s.scenario},
          {"seed", s.seed},
          {"vehicle", s.vehicle},
          {"duration_s", s.duration_s},
          {"distance_m", s.distance_m},
          {"distance_after_60s_m", s.distance_after_60s_m},
          {"max_speed_mps", s.max_speed_mps},
          {"max_lateral_accel_mps2", s.max_lateral_accel_mps2},
          {"max_yaw_rate_radps", s.max_yaw_rate_radps},
          {"rms_lateral_error_m", s.rms_lateral_error_m},
          {"max_lateral_error_m", s.max_lateral_error_m},
          {"max_longitudinal_error_m", s.max_longitudinal_error_m},
          {"max_traffic_vehicles", s.max_traffic_vehicles},
          {"traffic_light_stops", s.traffic_lights_stops},
          {"ego_arrived", s.ego_arrived},
          {"wall_time_s", wall_s},
          {"real_time_factor", wall_s > 0 ? s.duration_s / wall_s : 0.0}};
}

}  // namespace

int RunSimulate(const std::vector<std::string>& argv) {
  const auto parsed = ParseCommand(
      {"simulate", kUsage, {"quiet"}, {"out", "seed", "duration"}, 1, {"out"}}, argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs* args = &std::get<CliArgs>(parsed);
  const std::filesystem::path out_dir = *args->Option("out");
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    const sim::Scenario scenario = LoadScenarioWithOverrides(*args);
    std::filesystem::create_directories(out_dir);

    const bool quiet = args->Flag("quiet");
    if (!quiet) std::fprintf(stderr, "simulate: %s: building network and running SUMO...\n",
                             scenario.name.c_str());
    sim::TruthSimulation simulation(scenario, out_dir);
    sim::WriteTrafficCsv(simulation.sumo(), out_dir / "traffic.csv");
    sim::WritePathCsv(simulation.path(), simulation.terrain(), out_dir / "path.csv");

    TruthWriter writer(out_dir, simulation.vehicle().T_body_imu);
    ProgressBar bar("truth " + scenario.name);
    const double end_s = ToSeconds(simulation.end_ns());
    TruthSample sample;
    std::size_t n = 0;
    while (simulation.Next(&sample)) {
      writer.Write(sample);
      if (!quiet && ++n % 1000 == 0) {
        char detail[64];
        std::snprintf(detail, sizeof(detail), "t=%.0f s  %.0f m", ToSeconds(sample.t_ns),
                      sample.distance_m);
        bar.Update(ToSeconds(sample.t_ns) / end_s, detail);
      }
    }
    writer.Close();
    if (!quiet) bar.Finish();

    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    const sim::TruthSummary& s = simulation.summary();
    std::ofstream(out_dir / "summary.json") << SummaryJson(s, wall_s).dump(2) << "\n";
    std::printf(
        "%s (seed %llu, %s): %.1f s, %.1f m driven (%.1f m after t = 60 s), max speed %.2f m/s, "
        "max lateral accel %.2f m/s^2, max yaw rate %.3f rad/s, lateral tracking %.3f m RMS "
        "(max %.3f m), up to %d traffic vehicles, %d stops at lights; wall %.1f s (%.0fx real "
        "time) -> %s\n",
        s.scenario.c_str(), static_cast<unsigned long long>(s.seed), s.vehicle.c_str(),
        s.duration_s, s.distance_m, s.distance_after_60s_m, s.max_speed_mps,
        s.max_lateral_accel_mps2, s.max_yaw_rate_radps, s.rms_lateral_error_m,
        s.max_lateral_error_m, s.max_traffic_vehicles, s.traffic_lights_stops, wall_s,
        wall_s > 0 ? s.duration_s / wall_s : 0.0, out_dir.string().c_str());
    return 0;
  } catch (...) {
    return ExitCodeForCurrentException("simulate");
  }
}

}  // namespace statebench::app
