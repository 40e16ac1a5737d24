// statebench run SCENARIO.yaml --out DIR [--estimators factor_graph,ekf] [--seed N]
//                [--duration S] [--full-covariance] [--quiet]
//
// Simulator, sensors and estimators in one process, streaming (no disk in between): every
// measurement of the scenario's sensor setup goes, in arrival order, to every estimator; each
// estimator's real-time estimate at every IMU sample is written and scored against the truth.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/diagnostics_json.hpp"
#include "apps/progress_bar.hpp"
#include "apps/scenario_overrides.hpp"
#include "core/error.hpp"
#include "core/geodetic.hpp"
#include "estimator/estimator_factory.hpp"
#include "reports/estimate_writer.hpp"
#include "reports/metrics_json.hpp"
#include "simulator/sensor_run.hpp"

namespace statebench::app {
namespace {

constexpr const char* kUsage =
    "usage: statebench run SCENARIO.yaml --out DIR [--estimators factor_graph,ekf] [--seed N]\n"
    "                      [--duration S] [--full-covariance] [--quiet]\n"
    "  Runs the scenario's simulation, its sensor setup and each estimator in one process and\n"
    "  writes per estimator DIR/<estimator>/{estimate.csv, estimate.tum, diagnostics.json,\n"
    "  metrics.json}; prints a table of the main metrics.\n";

std::vector<std::string> SplitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

struct EstimatorRun {
  std::string name;
  std::unique_ptr<est::Estimator> estimator;
  std::unique_ptr<reports::EstimateWriter> writer;
  std::vector<StateEstimate> estimates;
};

}  // namespace

int RunRun(const std::vector<std::string>& argv) {
  const auto parsed = ParseCommand({"run", kUsage, {"quiet", "full-covariance"},
                                    {"out", "estimators", "seed", "duration"}, 1, {"out"}},
                                   argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs* args = &std::get<CliArgs>(parsed);
  const std::filesystem::path out_dir = *args->Option("out");
  const bool quiet = args->Flag("quiet");
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    const sim::Scenario scenario = LoadScenarioWithOverrides(*args);
    const std::vector<std::string> names =
        SplitList(args->Option("estimators").value_or("factor_graph,ekf"));
    if (names.empty()) throw std::invalid_argument("--estimators: no estimator named");
    const std::vector<std::string> known = est::KnownEstimators();
    for (const std::string& name : names) {
      if (std::find(known.begin(), known.end(), name) == known.end()) {
        std::string list;
        for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
        throw std::invalid_argument("--estimators: unknown estimator '" + name + "' (known: " +
                                    list + ")");
      }
    }
    const char* src = std::getenv("STATEBENCH_SOURCE_DIR");
    const std::filesystem::path estimators_dir =
        std::filesystem::path(src ? src : ".") / "scenarios/estimators";

    // Everything that can be checked before the run is: scenario, setup, estimator names and
    // options, so a typo fails in a second, not after the simulation.
    if (!quiet) {
      std::fprintf(stderr, "run: %s: building network, running SUMO, building the world...\n",
                   scenario.name.c_str());
    }
    sim::SensorRun run(scenario, out_dir);
    const YamlNode setup_node = YamlNode::LoadString(
        run.sensors().setup_yaml, run.sensors().setup.source.empty() ? "sensor setup"
                                                                      : run.sensors().setup.source);
    const est::EstimatorSensorSetup setup = est::ParseEstimatorSensorSetup(setup_node);
    std::vector<EstimatorRun> runs;
    for (const std::string& name : names) {
      est::EstimatorFiles files;
      files.options = estimators_dir / (name + ".yaml");
      files.vehicle = scenario.vehicle_file;
      EstimatorRun r;
      r.name = name;
      r.estimator = est::MakeEstimator(name, setup, files);
      r.writer = std::make_unique<reports::EstimateWriter>(out_dir / name,
                                                           args->Flag("full-covariance"));
      runs.push_back(std::move(r));
    }

    const LocalEnuFrame world_frame(scenario.origin);
    std::vector<TruthSample> truth;
    run.SetTruthObserver([&truth](const TruthSample& s) { truth.push_back(s); });
    ProgressBar bar("run " + scenario.name);
    const double end_s = ToSeconds(run.truth().end_ns());
    std::size_t n = 0;
    while (const auto m = run.Next()) {
      const auto* imu = std::get_if<ImuSample>(&*m);
      const bool output = imu != nullptr && imu->header.sensor_id == setup.imu_id;
      for (EstimatorRun& r : runs) {
        r.estimator->Add(*m);
        if (!output) continue;
        if (auto e = r.estimator->StateAt(imu->header.stamp_ns)) {
          // In the scenario's ENU frame, whatever origin the estimator chose.
          e->state.p_world = world_frame.ToEnu({e->latitude_deg, e->longitude_deg, e->altitude_m});
          r.writer->Write(*e);
          r.estimates.push_back(*e);
        }
      }
      if (output && !quiet && ++n % 500 == 0) {
        char detail[64];
        std::snprintf(detail, sizeof(detail), "t=%.0f s", ToSeconds(imu->header.stamp_ns));
        bar.Update(ToSeconds(imu->header.stamp_ns) / end_s, detail);
      }
    }
    if (!quiet) bar.Finish();
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    const auto reference = reports::ReferenceFromTruth(truth, setup.T_body_imu);
    std::printf("%s (seed %llu, %.0f s, %.0f m, wall %.1f s)\n", scenario.name.c_str(),
                static_cast<unsigned long long>(scenario.seed), end_s,
                run.truth().summary().distance_m, wall_s);
    std::printf("%-14s %8s %8s %8s %9s %9s %8s %8s %9s\n", "estimator", "x [m]", "y [m]",
                "z [m]", "yaw [rad]", "v_lon[m/s]", "APE [m]", "NEES(6)", "solve p99");
    nlohmann::json summary = nlohmann::json::object();
    for (EstimatorRun& r : runs) {
      r.writer->Close();
      const est::EstimatorDiagnostics diagnostics = r.estimator->diagnostics();
      const nlohmann::json diag = DiagnosticsJson(diagnostics);
      std::ofstream(out_dir / r.name / "diagnostics.json") << diag.dump(2) << "\n";
      reports::MetricsOptions mopt;
      mopt.skip_before_ns = diagnostics.initialized_at_ns;
      const reports::TrajectoryMetrics metrics =
          reports::ComputeTrajectoryMetrics(r.estimates, reference, mopt);
      nlohmann::json j = reports::ToJson(metrics);
      j["estimator"] = r.name;
      j["scenario"] = scenario.name;
      j["seed"] = scenario.seed;
      j["solve_ms_p99"] = diag["updates"]["solve_ms_p99"];
      std::ofstream(out_dir / r.name / "metrics.json") << j.dump(2) << "\n";
      summary[r.name] = j;
      std::printf("%-14s %8.3f %8.3f %8.3f %9.4f %9.3f %8.3f %8.2f %7.2fms\n", r.name.c_str(),
                  metrics.rmse_x_m, metrics.rmse_y_m, metrics.rmse_z_m, metrics.rmse_yaw_rad,
                  metrics.rmse_v_longitudinal_mps, metrics.ape_translation_m.rmse,
                  metrics.mean_pose_nees, diag["updates"]["solve_ms_p99"].get<double>());
    }
    summary["wall_time_s"] = wall_s;
    summary["real_time_factor"] = wall_s > 0 ? end_s / wall_s : 0.0;
    std::ofstream(out_dir / "run.json") << summary.dump(2) << "\n";
    return 0;
  } catch (...) {
    return ExitCodeForCurrentException("run");
  }
}

}  // namespace statebench::app
