// statebench estimate LOG --out DIR [--config OPTIONS.yaml] [--setup SETUP.yaml]
//                        [--batch] [--full-covariance] [--quiet]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>
#include <nlohmann/json.hpp>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/cpu_profile.hpp"
#include "apps/estimator_feed.hpp"
#include "apps/truth_stream.hpp"
#include "core/error.hpp"
#include "core/geodetic.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/estimator_factory.hpp"
#include "reports/estimate_writer.hpp"
#include "reports/metrics_json.hpp"
#include "sensors/log_reader.hpp"

namespace statebench::app {
namespace {

constexpr const char* kUsage =
    "usage: statebench estimate LOG --out DIR [--estimator factor_graph|ekf] [--config "
    "OPTIONS.yaml]\n"
    "                           [--setup SETUP.yaml] [--vehicle VEHICLE.yaml]\n"
    "                           [--batch] [--full-covariance] [--quiet]\n"
    "  Runs an estimator (default: the factor graph) on a recorded log (simulated or converted\n"
    "  from a real vehicle) and writes the estimate at IMU rate (estimate.csv with the covariance\n"
    "  diagonal, or the full covariance with --full-covariance; estimate.tum), diagnostics.json,\n"
    "  and metrics.json when the log holds truth. --config defaults to\n"
    "  scenarios/estimators/<estimator>.yaml, --setup to the log's own sensor setup; the EKF\n"
    "  baseline also needs the vehicle parameters (--vehicle "
    "scenarios/vehicles/quadricycle.yaml).\n"
    "  --batch: the factor graph's full-batch smoother (every state solved at the end of the log,\n"
    "  no marginalisation; batch: true in the options), the bound of the fixed-lag smoother.\n"
    "  Exit code 3 when the estimator never initialised (stderr says what it waited for).\n";

std::filesystem::path DefaultEstimatorConfig(const std::string& estimator) {
  const char* src = std::getenv("STATEBENCH_SOURCE_DIR");
  return std::filesystem::path(src ? src : ".") / "scenarios/estimators" / (estimator + ".yaml");
}

}  // namespace

int RunEstimate(const std::vector<std::string>& argv) {
  const auto parsed = ParseCommand({"estimate",
                                    kUsage,
                                    {"quiet", "full-covariance", "batch"},
                                    {"out", "config", "setup", "estimator", "vehicle"},
                                    1,
                                    {"out"}},
                                   argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs* args = &std::get<CliArgs>(parsed);
  const std::filesystem::path log_dir = args->positional()[0];
  const std::filesystem::path out_dir = *args->Option("out");
  const bool quiet = args->Flag("quiet");
  const auto wall_start = std::chrono::steady_clock::now();
  const CpuProfile cpu;
  try {
    sensors::LogReader reader(log_dir);
    const std::filesystem::path setup_file = SetupFileOf(*args, reader, log_dir);
    const est::EstimatorSensorSetup setup = est::LoadEstimatorSensorSetup(setup_file);
    const std::string name = args->Option("estimator").value_or("factor_graph");
    est::EstimatorFiles files;
    files.options = args->Option("config").value_or(DefaultEstimatorConfig(name).string());
    if (const auto vehicle = args->Option("vehicle")) files.vehicle = *vehicle;
    files.batch = args->Flag("batch");
    // Estimators anchor their ENU frame where they like (configured origin or first fix); the
    // estimate is re-expressed in the log's ENU frame through its WGS84 position so that it
    // compares with the log's truth (the frames' axes differ by the meridian convergence
    // between the two origins, micro-radians over a drive, which is neglected).
    std::optional<LocalEnuFrame> log_frame;
    if (reader.manifest().origin) log_frame.emplace(*reader.manifest().origin);

    // The truth is streamed into the scorer as the log is read (TruthStream): it holds the
    // truth of the last instants, and scores when the file holds a sample at all.
    std::optional<TruthStream> truth;
    if (reader.manifest().truth_csv) truth.emplace(log_dir / *reader.manifest().truth_csv);
    const bool has_truth = truth && !truth->empty();

    EstimatorFeed feed(setup.imu_id, log_frame);
    feed.Add(name, name, out_dir, est::MakeEstimator(name, setup, files),
             args->Flag("full-covariance"));
    double end_s = 0.0;
    if (has_truth) {
      // The truth of the IMU as it is mounted (as `statebench run` scores), where the log says;
      // else the setup's mount (a log recorded before the field, or a real one).
      feed.ScoreAgainstTruth(reader.manifest().truth_imu_mount.value_or(setup.T_body_imu), {});
      feed.WriteDetails(out_dir);
      end_s = ToSeconds(LastRowStamp(log_dir / *reader.manifest().truth_csv).value_or(0));
    }
    FeedProgress progress("estimate " + log_dir.filename().string(), end_s, quiet);
    const auto next = [&reader] {
      const StageScope stage(Stage::kReading);
      return reader.Next();
    };
    std::optional<TimeNs> first_ns;
    std::optional<TimeNs> last_ns;
    while (const auto m = next()) {
      if (has_truth) {
        const MeasurementHeader& h = HeaderOf(*m);
        truth->FeedUpTo(std::max(h.stamp_ns, h.arrival_ns), feed);
      }
      if (const auto t = feed.Feed(*m)) {
        progress.Epoch(*t);
        if (!first_ns) first_ns = *t;
        last_ns = *t;
      }
    }
    if (has_truth) truth->FeedRest(feed);  // what comes after the log's last message
    progress.Finish();
    const std::optional<std::string> truth_error = truth ? truth->error() : std::nullopt;
    EstimatorScore score = feed.Finish().front();
    const FedEstimator& fed = feed.estimators().front();
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    std::printf("%s: %zu estimates at IMU rate -> %s (wall %.1f s)\n",
                fed.estimator->name().c_str(), fed.estimates, out_dir.string().c_str(),
                wall_s);
    // Where the CPU time went (log reading, estimator, writing, scoring), over the logged span.
    const double logged_s = first_ns ? ToSeconds(*last_ns - *first_ns) : 0.0;
    nlohmann::json profile = {{"log", log_dir.string()},
                              {"logged_s", logged_s},
                              {"wall_time_s", wall_s},
                              {"cpu", cpu.Json(feed.estimators(), logged_s)}};
    std::ofstream(out_dir / "profile.json") << profile.dump(2) << "\n";
    const std::optional<std::string> no_estimate = NoEstimateMessage(fed, score);
    if (!no_estimate) {
      // Truth-free (diagnostics.json output_step): how far the output jumps between samples.
      const reports::OutputSteps& steps = score.output_steps;
      std::printf(
          "output step beyond its own motion: position p50 %.4f p99 %.4f max %.4f m, yaw p99 "
          "%.5f max %.5f rad\n",
          steps.position_m.p50, steps.position_m.p99, steps.position_m.max, steps.yaw_rad.p99,
          steps.yaw_rad.max);
    }
    if (has_truth) {
      nlohmann::json& j = score.metrics_json;
      j["estimator"] = fed.estimator->name();
      j["log"] = log_dir.string();
      j["wall_time_s"] = wall_s;
      WriteMetrics(out_dir, score);
    }
    if (has_truth && !no_estimate) {
      const reports::TrajectoryMetrics& metrics = score.metrics;
      std::printf(
          "RMSE  x %.3f m  y %.3f m  z %.3f m  yaw %.4f rad  v_long %.3f m/s  | APE %.3f m  "
          "NEES(6) %.2f  over %.0f m\n",
          metrics.rmse_x_m, metrics.rmse_y_m, metrics.rmse_z_m, metrics.rmse_yaw_rad,
          metrics.rmse_v_longitudinal_mps, metrics.ape_translation_m.rmse, metrics.mean_pose_nees,
          metrics.distance_m);
    }
    if (truth_error) std::fprintf(stderr, "warning: truth: %s\n", truth_error->c_str());
    if (no_estimate) std::fprintf(stderr, "error: %s\n", no_estimate->c_str());
    if (reader.error()) {
      std::fprintf(stderr, "error: %s (the estimate up to that point was written)\n",
                   reader.error()->c_str());
      return 2;
    }
    return no_estimate ? kExitNoEstimate : 0;
  } catch (...) {
    return ExitCodeForCurrentException("estimate");
  }
}

}  // namespace statebench::app
