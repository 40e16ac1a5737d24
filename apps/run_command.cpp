// statebench run SCENARIO.yaml --out DIR [--estimators a,b] [--seed N] [--duration S]
//                [--threads N] [--full-covariance] [--quiet]
//
// Simulator, sensors and estimators in one process, streaming (no disk in between): every
// measurement of the scenario's sensor setup goes, in arrival order, to every estimator of the
// scenario's `estimators:` list; each estimator's real-time estimate at every IMU sample is
// written and scored against the truth.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/cpu_profile.hpp"
#include "apps/estimator_feed.hpp"
#include "apps/lidar_odometry_cache.hpp"
#include "apps/memory_trace.hpp"
#include "apps/scenario_estimators.hpp"
#include "apps/scenario_overrides.hpp"
#include "apps/scored_outages.hpp"
#include "apps/stage_cache_options.hpp"
#include "apps/thread_limit.hpp"
#include "core/error.hpp"
#include "core/geodetic.hpp"
#include "estimator/estimator_factory.hpp"
#include "reports/estimate_writer.hpp"
#include "reports/metrics_json.hpp"
#include "simulator/scenario_mismatch.hpp"
#include "simulator/scenario_sensors.hpp"
#include "simulator/sensor_run.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage: statebench run SCENARIO.yaml --out DIR [--estimators NAME,...] [--seed N]\n"
    "                      [--duration S] [--threads N] [--full-covariance] [--quiet]\n"
    "                      [--cache DIR [--cache-limit-gb G]]\n"
    "  Runs the scenario's simulation, its sensor setup and each estimator of its `estimators:`\n"
    "  list (default: factor_graph and ekf) in one process and writes per estimator\n"
    "  DIR/<name>/{estimator_config.yaml, estimate.csv, estimate.tum, diagnostics.json,\n"
    "  metrics.json} and DIR/run.json; prints a table of the main metrics. --estimators picks\n"
    "  entries of the list by name or by type. --cache keeps the SUMO result and every sensor's\n"
    "  stream in DIR under a hash of what they depend on and reuses them (same bits; run.json\n"
    "  counts the hits); the least recently used entries go beyond G GB (default 20).\n"
    "  --threads N: at most N threads (default: every core); the results do not depend on it.\n"
    "  Exit code 3 when an estimator never initialised (all else written; stderr says what it\n"
    "  waited for).\n";

// The scenario's stream faults (outages and injected ones) and how many measurements each hit.
nlohmann::json FaultsJson(const MeasurementFaultInjector& injector) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i < injector.faults().size(); ++i) {
    const MeasurementFault& f = injector.faults()[i];
    nlohmann::json j = {{"type", std::string(MeasurementFaultName(f.kind))},
                        {"sensors", f.sensors},
                        {"start_s", f.start_s},
                        {"affected", injector.affected()[i]}};
    if (std::isfinite(f.end_s)) j["end_s"] = f.end_s;
    out.push_back(j);
  }
  return out;
}

// What the scenario's `mismatch:` drew for this run.
nlohmann::json MismatchJson(const std::vector<sim::SensorMismatch>& sensors,
                            const sim::VehicleMismatch& vehicle) {
  const auto vec = [](const Vec3& v) { return nlohmann::json{v.x(), v.y(), v.z()}; };
  nlohmann::json per_sensor = nlohmann::json::object();
  for (const sim::SensorMismatch& m : sensors) {
    per_sensor[m.id] = {{"mount_translation_m", vec(m.mount_translation_m)},
                        {"mount_rotation_deg", vec(m.mount_rotation_deg)},
                        {"clock_offset_s", m.clock_offset_s},
                        {"reported_covariance_scale", m.reported_covariance_scale},
                        {"slow_error_variance_factor", m.slow_error_variance_factor},
                        {"gyro_noise_factor", m.gyro_noise_factor},
                        {"gyro_walk_factor", m.gyro_walk_factor},
                        {"accel_noise_factor", m.accel_noise_factor},
                        {"accel_walk_factor", m.accel_walk_factor}};
  }
  return {{"sensors", per_sensor},
          {"vehicle",
           {{"file", vehicle.file.string()},
            {"mass_factor", vehicle.mass_factor},
            {"cornering_stiffness_front_factor", vehicle.cornering_stiffness_front_factor},
            {"cornering_stiffness_rear_factor", vehicle.cornering_stiffness_rear_factor}}}};
}

}  // namespace

int RunRun(const std::vector<std::string>& argv) {
  const auto parsed =
      ParseCommand({"run",
                    kUsage,
                    {"quiet", "full-covariance"},
                    {"out", "estimators", "seed", "duration", "threads", "cache", "cache-limit-gb"},
                    1,
                    {"out"}},
                   argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs* args = &std::get<CliArgs>(parsed);
  const fs::path out_dir = *args->Option("out");
  const bool quiet = args->Flag("quiet");
  const auto wall_start = std::chrono::steady_clock::now();
  const CpuProfile cpu;
  try {
    const ThreadLimit threads(ThreadsOption(*args));
    const sim::Scenario scenario = LoadScenarioWithOverrides(*args);
    std::vector<sim::EstimatorSpec> specs = sim::ScenarioEstimators(scenario);
    if (const auto option = args->Option("estimators")) {
      const std::vector<std::string> names = SplitList(*option);
      if (names.empty()) throw std::invalid_argument("--estimators: no estimator named");
      try {
        specs = ChooseEstimators(specs, names, scenario.file.string());
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("--estimators: ") + e.what());
      }
    }

    // Everything that can be checked before the simulation is: scenario, sensor setup (read
    // without running SUMO), each estimator's options and whether they fit the setup, so a typo
    // fails in a second, not after the simulation.
    const sim::ScenarioSensors sensors = sim::LoadScenarioSensors(scenario);
    const est::EstimatorSensorSetup setup = EstimatorSetupOf(sensors);
    // The vehicle parameters the estimators are told: with a `mismatch:`, drawn around the
    // simulator's (scenario_mismatch.hpp).
    std::optional<sim::VehicleMismatch> vehicle;
    if (scenario.mismatch) {
      fs::create_directories(out_dir);
      vehicle = sim::WriteEstimatorVehicleFile(*scenario.mismatch, scenario.seed,
                                               scenario.vehicle_file,
                                               out_dir / "vehicle_estimators.yaml");
    }
    std::unique_ptr<StageCache> cache = OpenStageCache(*args);
    sim::SensorRunOptions run_options;
    if (cache) run_options.cache = {cache.get(), BuildIdentity()};
    // In the scenario's ENU frame, whatever origin each estimator chose.
    EstimatorFeed feed(setup.imu_id, LocalEnuFrame(scenario.origin));
    // Factor graphs with the same lidar odometry and a prior of their own (gyro, constant
    // velocity) register each scan once between them (the first to ask pays: its CPU time
    // includes the registration); with --cache, runs with the same inputs read them.
    std::unique_ptr<CachedRegistrationStore> registrations;
    if (cache) {
      if (const auto inputs = sim::EstimatorInputsKey(scenario, sensors, run_options.sumo,
                                                      scenario.seed, BuildIdentity())) {
        registrations = std::make_unique<CachedRegistrationStore>(*cache, *inputs);
      }
    }
    est::LidarOdometryPool lidar_pool(registrations.get());
    for (const sim::EstimatorSpec& spec : specs) {
      const fs::path dir = out_dir / spec.label;
      feed.Add(spec.label, spec.type, dir,
               MakeScenarioEstimator(spec, scenario, setup, dir,
                                     vehicle ? vehicle->file : fs::path(), &lidar_pool),
               args->Flag("full-covariance"), spec.inputs);
    }

    if (!quiet) {
      std::fprintf(stderr, "run: %s: building network, running SUMO, building the world...\n",
                   scenario.name.c_str());
    }
    sim::SensorRun run(scenario, out_dir, run_options);
    // Scored against the truth of the IMU as mounted (with a mismatch, not where the setup says).
    feed.ScoreAgainstTruth(run.T_body_imu(), ScoredOutages(run.sensors(), run.truth().end_ns()));
    feed.WriteDetails(out_dir);
    run.SetTruthObserver([&feed](const TruthSample& s) { feed.AddTruth(s); });
    const double end_s = ToSeconds(run.truth().end_ns());
    FeedProgress progress("run " + scenario.name, end_s, quiet);
    MemoryTrace memory;
    while (const auto m = run.Next()) {
      if (const auto t = feed.Feed(*m)) {
        progress.Epoch(*t);
        memory.At(*t);
      }
    }
    progress.Finish();
    lidar_pool.Finish();  // the run is complete: its registrations go into the cache
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    const double distance_m = run.truth().summary().distance_m;
    std::printf("%s (seed %llu, %.0f s, %.0f m, wall %.1f s)\n", scenario.name.c_str(),
                static_cast<unsigned long long>(scenario.seed), end_s, distance_m, wall_s);
    std::printf("%-16s %8s %8s %8s %9s %9s %8s %8s %9s\n", "estimator", "x [m]", "y [m]", "z [m]",
                "yaw [rad]", "v_lon[m/s]", "APE [m]", "NEES(6)", "solve p99");
    nlohmann::json estimators = nlohmann::json::array();
    const std::vector<EstimatorScore> scores = feed.Finish();
    std::vector<std::string> no_estimate;  // one line per estimator that wrote no estimate
    for (std::size_t i = 0; i < scores.size(); ++i) {
      const FedEstimator& r = feed.estimators()[i];
      EstimatorScore s = scores[i];
      nlohmann::json& j = s.metrics_json;
      j["estimator"] = r.label;
      j["type"] = r.type;
      j["scenario"] = scenario.name;
      j["seed"] = scenario.seed;
      j["solve_ms_p99"] = s.diagnostics_json["updates"]["solve_ms_p99"];
      WriteMetrics(r.dir, s);
      estimators.push_back(
          {{"label", r.label},
           {"type", r.type},
           {"inputs", r.inputs.empty() ? nlohmann::json("all") : nlohmann::json(r.inputs)},
           {"config", (fs::path(r.label) / "estimator_config.yaml").string()},
           {"metrics", j}});
      if (const auto message = NoEstimateMessage(r, s)) {
        // Its metrics are unavailable, not zero (metrics.json: availability).
        estimators.back()["no_estimate"] = *message;
        no_estimate.push_back(*message);
        std::printf("%-16s no estimate: %s\n", r.label.c_str(),
                    message->substr(r.label.size() + 1).c_str());
        continue;
      }
      const reports::TrajectoryMetrics& metrics = s.metrics;
      std::printf("%-16s %8.3f %8.3f %8.3f %9.4f %9.3f %8.3f %8.2f %7.2fms\n", r.label.c_str(),
                  metrics.rmse_x_m, metrics.rmse_y_m, metrics.rmse_z_m, metrics.rmse_yaw_rad,
                  metrics.rmse_v_longitudinal_mps, metrics.ape_translation_m.rmse,
                  metrics.mean_pose_nees, j["solve_ms_p99"].get<double>());
    }
    nlohmann::json summary = {{"scenario", scenario.name},
                              {"file", scenario.file.string()},
                              {"seed", scenario.seed},
                              {"simulated_s", end_s},
                              {"distance_m", distance_m},
                              {"wall_time_s", wall_s},
                              {"real_time_factor", wall_s > 0 ? end_s / wall_s : 0.0},
                              {"estimators", estimators}};
    summary["faults"] = FaultsJson(run.faults());
    if (scenario.mismatch) summary["mismatch"] = MismatchJson(sensors.mismatch, *vehicle);
    summary["memory"] = memory.Json();
    summary["cpu"] = cpu.Json(feed.estimators(), end_s);
    summary["cpu"]["threads"] = ThreadLimit::Threads();
    for (const auto& [registered, reused] : lidar_pool.Counts()) {
      summary["shared_lidar_odometry"].push_back({{"registered", registered}, {"reused", reused}});
    }
    if (cache) {
      summary["cache"] = CacheCountsJson(*cache);
      cache->Prune();
    }
    std::ofstream(out_dir / "run.json") << summary.dump(2) << "\n";
    for (const std::string& message : no_estimate) {
      std::fprintf(stderr, "error: %s\n", message.c_str());
    }
    return no_estimate.empty() ? 0 : kExitNoEstimate;
  } catch (...) {
    return ExitCodeForCurrentException("run");
  }
}

}  // namespace statebench::app
