// statebench odometry LOG --out DIR [--setup SETUP.yaml] [--lidar ID] [--quiet]
//
// Lidar-only odometry of one lidar of a recorded log. The trajectory of the lidar frame is
// written in TUM (odometry.tum): relative motions composed from the truth's lidar pose at the
// first accepted scan when the log has truth (else identity). With truth, the KITTI relative
// error of the lidar frame's trajectory goes to metrics.json and the console.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "core/error.hpp"
#include "core/truth_io.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/lidar_odometry.hpp"
#include "reports/metrics_json.hpp"
#include "reports/trajectory_metrics.hpp"
#include "sensors/log_reader.hpp"

namespace statebench::app {
namespace {

constexpr const char* kUsage =
    "usage: statebench odometry LOG --out DIR [--setup SETUP.yaml] [--lidar ID]\n"
    "                           [--icp projected|point-to-point] [--quiet]\n"
    "  Lidar-only odometry (KISS-ICP-style, surface-projected robust ICP) of the log's first\n"
    "  lidar (or --lidar ID). Writes odometry.tum (lidar frame in the log's world, started at\n"
    "  the truth's lidar pose when the log has truth), scans.csv (per-scan diagnostics),\n"
    "  diagnostics.json, and metrics.json with\n"
    "  the KITTI relative error when the log holds truth. --icp point-to-point runs plain\n"
    "  point-to-point ICP (KISS-ICP's metric) for comparison.\n";

void WriteTum(std::ofstream& out, TimeNs t_ns, const SE3& T) {
  const Quat& q = T.rotation();
  const Vec3& p = T.translation();
  char line[256];
  std::snprintf(line, sizeof(line), "%.9f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", ToSeconds(t_ns),
                p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w());
  out << line;
}

}  // namespace

int RunOdometry(const std::vector<std::string>& argv) {
  const auto parsed = ParseCommand(
      {"odometry", kUsage, {"quiet"}, {"out", "setup", "lidar", "icp"}, 1, {"out"}}, argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs* args = &std::get<CliArgs>(parsed);
  const std::filesystem::path log_dir = args->positional()[0];
  const std::filesystem::path out_dir = *args->Option("out");
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    sensors::LogReader reader(log_dir);
    const std::filesystem::path setup_file = SetupFileOf(*args, reader, log_dir);
    const est::EstimatorSensorSetup setup = est::LoadEstimatorSensorSetup(setup_file);
    const est::EstimatorSensor* lidar = nullptr;
    for (const auto& s : setup.sensors) {
      if (s.kind != est::SensorKind::kLidar) continue;
      if (!args->Option("lidar") || *args->Option("lidar") == s.id) {
        lidar = &s;
        break;
      }
    }
    if (lidar == nullptr) {
      throw InputError(setup_file.string() + ": no lidar" +
                       (args->Option("lidar") ? " with id '" + *args->Option("lidar") + "'" : ""));
    }

    std::vector<TruthSample> truth;
    if (reader.manifest().truth_csv) {
      truth = ReadTruthCsv(log_dir / *reader.manifest().truth_csv).samples;
    }
    const std::vector<reports::ReferenceState> reference =
        truth.empty() ? std::vector<reports::ReferenceState>{}
                      : reports::ReferenceFromTruth(truth, lidar->T_body_sensor);

    std::filesystem::create_directories(out_dir);
    std::ofstream tum(out_dir / "odometry.tum");
    std::ofstream per_scan(out_dir / "scans.csv");
    per_scan << "t_s,accepted,reason,points_in,non_finite,points_registered,iterations,"
                "correspondences,degenerate,degenerate_directions,threshold_m,residual_sigma_m\n";
    est::LidarOdometryOptions odometry_options;
    const std::string icp = args->Option("icp").value_or("projected");
    if (icp == "point-to-point") {
      odometry_options.icp.metric = est::IcpMetric::kPointToPoint;
    } else if (icp != "projected") {
      throw InputError("--icp: expected 'projected' or 'point-to-point', got '" + icp + "'");
    }
    est::LidarOdometry odometry(odometry_options);
    double register_s = 0.0;
    SE3 T_world_odom;  // world of the log <- odometry world (lidar at its first scan)
    std::vector<StateEstimate> estimates;
    std::map<std::string, std::size_t> rejected;
    std::size_t scans = 0, accepted = 0, degenerate = 0;
    double points_in = 0.0, points_registered = 0.0, iterations = 0.0;
    while (const auto m = reader.Next()) {
      const auto* scan = std::get_if<LidarScan>(&*m);
      if (scan == nullptr || scan->header.sensor_id != lidar->id) continue;
      ++scans;
      const auto register_start = std::chrono::steady_clock::now();
      const est::LidarOdometryResult r = odometry.RegisterScan(*scan);
      register_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - register_start).count();
      points_in += static_cast<double>(r.diagnostics.points_in);
      const est::LidarOdometryDiagnostics& d = r.diagnostics;
      per_scan << ToSeconds(r.stamp_ns) << ',' << (r.accepted ? 1 : 0) << ",\"" << r.reject_reason
               << "\"," << d.points_in << ',' << d.non_finite << ',' << d.points_registered << ','
               << d.iterations << ',' << d.correspondences << ',' << (d.degenerate ? 1 : 0) << ','
               << d.degenerate_directions << ',' << d.threshold_m << ',' << d.residual_sigma_m
               << '\n';
      if (!r.accepted) {
        ++rejected[r.reject_reason.substr(0, r.reject_reason.find(" ("))];
        continue;
      }
      ++accepted;
      if (r.first_scan && !reference.empty()) {
        if (const auto ref = reports::InterpolateReference(reference, r.stamp_ns)) {
          T_world_odom = ref->T_world_frame;
        }
      }
      points_registered += static_cast<double>(r.diagnostics.points_registered);
      iterations += r.diagnostics.iterations;
      degenerate += r.diagnostics.degenerate ? 1 : 0;
      const SE3 T_world_lidar = T_world_odom * r.T_world_lidar;
      WriteTum(tum, r.stamp_ns, T_world_lidar);
      StateEstimate e;
      e.state.t_ns = r.stamp_ns;
      e.state.q_world_imu = T_world_lidar.rotation();
      e.state.p_world = T_world_lidar.translation();
      estimates.push_back(e);
      if (!args->Flag("quiet") && accepted % 100 == 0) {
        std::fprintf(stderr, "\rodometry: %zu scans, t=%.0f s", accepted, ToSeconds(r.stamp_ns));
      }
    }
    tum.close();
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (!args->Flag("quiet")) std::fprintf(stderr, "\n");
    nlohmann::json diag = {
        {"lidar", lidar->id},
        {"scans", scans},
        {"accepted", accepted},
        {"rejected", rejected},
        {"degenerate", degenerate},
        {"mean_points_in", scans ? points_in / scans : 0.0},
        {"mean_points_registered", accepted ? points_registered / accepted : 0.0},
        {"mean_iterations", accepted ? iterations / accepted : 0.0},
        {"icp", icp},
        {"register_ms_mean", scans ? 1e3 * register_s / scans : 0.0},
        {"wall_time_s", wall_s}};
    std::ofstream(out_dir / "diagnostics.json") << diag.dump(2) << "\n";
    std::printf(
        "odometry %s (%s): %zu/%zu scans accepted (%zu degenerate) -> %s (wall %.1f s, "
        "registration %.1f ms/scan)\n",
        lidar->id.c_str(), icp.c_str(), accepted, scans, degenerate, out_dir.string().c_str(),
        wall_s, scans ? 1e3 * register_s / static_cast<double>(scans) : 0.0);
    if (!reference.empty()) {
      const reports::TrajectoryMetrics metrics =
          reports::ComputeTrajectoryMetrics(estimates, reference, {});
      nlohmann::json j = reports::ToJson(metrics);
      j["lidar"] = lidar->id;
      j["log"] = log_dir.string();
      std::ofstream(out_dir / "metrics.json") << j.dump(2) << "\n";
      std::printf(
          "KITTI  translation %.3f %%  rotation %.5f deg/m  (%zu segments)  | APE %.3f m  over "
          "%.0f m\n",
          metrics.kitti_translation_percent, metrics.kitti_rotation_deg_per_m,
          metrics.kitti_segments, metrics.ape_translation_m.rmse, metrics.distance_m);
    }
    if (reader.error()) {
      std::fprintf(stderr, "error: %s\n", reader.error()->c_str());
      return 2;
    }
    return 0;
  } catch (...) {
    return ExitCodeForCurrentException("odometry");
  }
}

}  // namespace statebench::app
