// statebench odometry SCENARIO.yaml|LOG --out DIR [--lidar ID|all] [--duration S] [--seed N]
//                     [--setup SETUP.yaml] [--icp projected|point-to-point] [--quiet]
//
// Lidar-only odometry, from a scenario simulated in-process (streaming, nothing on disk but the
// outputs) or from a recorded log. With several lidars (default --lidar all) their scans are
// merged per scan period (estimator/lidar_scan_merger.hpp) into the first lidar's frame; the
// odometry tracks that frame. The trajectory goes to odometry.tum: relative motions composed from
// the truth's pose of that frame at the first accepted scan (identity without truth). With truth,
// the KITTI relative error (segments 100..800 m) and the ratio of the odometry's travelled
// distance to the true one go to metrics.json and the console.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/progress_bar.hpp"
#include "apps/scenario_overrides.hpp"
#include "core/error.hpp"
#include "core/truth_io.hpp"
#include "core/yaml_node.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/lidar_odometry.hpp"
#include "estimator/lidar_scan_merger.hpp"
#include "reports/metrics_json.hpp"
#include "reports/trajectory_metrics.hpp"
#include "sensors/log_reader.hpp"
#include "simulator/sensor_run.hpp"

namespace statebench::app {
namespace {

constexpr const char* kUsage =
    "usage: statebench odometry SCENARIO.yaml|LOG --out DIR [--lidar ID|all] [--duration S]\n"
    "                           [--seed N] [--setup SETUP.yaml] [--icp projected|point-to-point]\n"
    "                           [--quiet]\n"
    "  Lidar-only odometry (KISS-ICP-style, surface-projected robust ICP). SCENARIO.yaml: the\n"
    "  simulation and its sensors run in-process (--duration, --seed override the scenario);\n"
    "  LOG: a recorded log (--setup overrides its setup). --lidar all (default) merges every\n"
    "  lidar of the setup per scan period into the first lidar's frame; --lidar ID uses one.\n"
    "  Writes odometry.tum (that frame in the world, started at the truth's pose), truth.tum\n"
    "  (the truth of that frame at the same stamps), scans.csv\n"
    "  (per-scan diagnostics), diagnostics.json and, with truth, metrics.json (KITTI relative\n"
    "  error over 100..800 m, APE, odometry/true distance). --icp point-to-point runs plain\n"
    "  point-to-point ICP (KISS-ICP's metric) for comparison.\n";

struct TimedPose {
  TimeNs t_ns = 0;
  SE3 T_odom_lidar;
};

// Lidars of the setup that --lidar selects, with their mounts in the first one's frame.
std::vector<est::LidarMount> SelectLidars(const est::EstimatorSensorSetup& setup,
                                          const std::optional<std::string>& which,
                                          SE3* T_body_ref) {
  std::vector<const est::EstimatorSensor*> lidars;
  for (const auto& s : setup.sensors) {
    if (s.kind != est::SensorKind::kLidar) continue;
    if (!which || *which == "all" || *which == s.id) lidars.push_back(&s);
  }
  if (lidars.empty()) {
    throw InputError(setup.source + ": no lidar" +
                     (which && *which != "all" ? " with id '" + *which + "'" : ""));
  }
  *T_body_ref = lidars.front()->T_body_sensor;
  std::vector<est::LidarMount> mounts;
  for (const est::EstimatorSensor* s : lidars) {
    mounts.push_back({s->id, T_body_ref->Inverse() * s->T_body_sensor});
  }
  return mounts;
}

// Scans in, one odometry step per scan period out (merged when several lidars), per-scan rows.
class OdometryRun {
 public:
  OdometryRun(std::vector<est::LidarMount> mounts, const est::LidarOdometryOptions& options,
              const std::filesystem::path& out_dir)
      : odometry_(options), per_scan_(out_dir / "scans.csv") {
    ids_ = mounts;
    if (mounts.size() > 1) merger_.emplace(std::move(mounts));
    per_scan_ << "t_s,accepted,reason,points_in,non_finite,points_registered,iterations,"
                 "correspondences,degenerate,degenerate_directions,threshold_m,residual_sigma_m,"
                 "register_ms,info_min,info_max,weak_x,weak_y,weak_z,weak_roll,weak_"
                 "pitch,weak_yaw\n";
  }

  // Returns the stamp of the last scan registered, if any.
  std::optional<TimeNs> Add(const LidarScan& scan) {
    bool ours = false;
    for (const auto& m : ids_) ours = ours || m.id == scan.header.sensor_id;
    if (!ours) return std::nullopt;
    if (!merger_) return Register(scan);
    std::optional<TimeNs> last;
    for (const LidarScan& merged : merger_->Add(scan)) last = Register(merged);
    return last;
  }

  void Finish() {
    if (merger_) {
      for (const LidarScan& merged : merger_->Flush()) Register(merged);
    }
  }

  const std::vector<TimedPose>& poses() const { return poses_; }
  const std::optional<est::LidarScanMerger>& merger() const { return merger_; }

  std::size_t scans = 0, accepted = 0, degenerate = 0;
  double register_s = 0.0, points_in = 0.0, points_registered = 0.0, iterations = 0.0;
  std::map<std::string, std::size_t> rejected;

 private:
  TimeNs Register(const LidarScan& scan) {
    ++scans;
    const auto start = std::chrono::steady_clock::now();
    const est::LidarOdometryResult r = odometry_.RegisterScan(scan);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    register_s += s;
    const est::LidarOdometryDiagnostics& d = r.diagnostics;
    points_in += static_cast<double>(d.points_in);
    per_scan_ << ToSeconds(r.stamp_ns) << ',' << (r.accepted ? 1 : 0) << ",\"" << r.reject_reason
              << "\"," << d.points_in << ',' << d.non_finite << ',' << d.points_registered << ','
              << d.iterations << ',' << d.correspondences << ',' << (d.degenerate ? 1 : 0) << ','
              << d.degenerate_directions << ',' << d.threshold_m << ',' << d.residual_sigma_m << ','
              << 1e3 * s;
    for (int k : {0, 5}) per_scan_ << ',' << d.information_eigenvalues(k);
    for (int k = 0; k < 6; ++k) per_scan_ << ',' << d.weakest_direction(k);
    per_scan_ << '\n';
    if (!r.accepted) {
      ++rejected[r.reject_reason.substr(0, r.reject_reason.find(" ("))];
      return r.stamp_ns;
    }
    ++accepted;
    points_registered += static_cast<double>(d.points_registered);
    iterations += d.iterations;
    degenerate += d.degenerate ? 1 : 0;
    poses_.push_back({r.stamp_ns, r.T_world_lidar});
    return r.stamp_ns;
  }

  est::LidarOdometry odometry_;
  std::vector<est::LidarMount> ids_;
  std::optional<est::LidarScanMerger> merger_;
  std::ofstream per_scan_;
  std::vector<TimedPose> poses_;
};

void WriteTum(std::ofstream& out, TimeNs t_ns, const SE3& T) {
  const Quat& q = T.rotation();
  const Vec3& p = T.translation();
  char line[256];
  std::snprintf(line, sizeof(line), "%.9f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", ToSeconds(t_ns),
                p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w());
  out << line;
}

// Odometry poses in the world (anchored at the reference's pose at the first one when there is
// a reference), as estimates for the metrics.
std::vector<StateEstimate> ToWorld(const std::vector<TimedPose>& poses,
                                   const std::vector<reports::ReferenceState>& reference) {
  SE3 T_world_odom;
  if (!poses.empty() && !reference.empty()) {
    if (const auto ref = reports::InterpolateReference(reference, poses.front().t_ns)) {
      T_world_odom = ref->T_world_frame;
    }
  }
  std::vector<StateEstimate> out;
  for (const TimedPose& p : poses) {
    const SE3 T_world_lidar = T_world_odom * p.T_odom_lidar;
    StateEstimate e;
    e.state.t_ns = p.t_ns;
    e.state.q_world_imu = T_world_lidar.rotation();
    e.state.p_world = T_world_lidar.translation();
    out.push_back(e);
  }
  return out;
}

// Path length of the estimates and of the reference at the same stamps (inside its span).
std::pair<double, double> TravelledDistances(const std::vector<StateEstimate>& estimates,
                                             const std::vector<reports::ReferenceState>& ref) {
  double odometry_m = 0.0, truth_m = 0.0;
  std::optional<Vec3> last_est, last_ref;
  for (const StateEstimate& e : estimates) {
    const auto r = reports::InterpolateReference(ref, e.state.t_ns);
    if (!r) continue;
    if (last_est) {
      odometry_m += (e.state.p_world - *last_est).norm();
      truth_m += (r->T_world_frame.translation() - *last_ref).norm();
    }
    last_est = e.state.p_world;
    last_ref = r->T_world_frame.translation();
  }
  return {odometry_m, truth_m};
}

}  // namespace

int RunOdometry(const std::vector<std::string>& argv) {
  const auto parsed = ParseCommand({"odometry",
                                    kUsage,
                                    {"quiet"},
                                    {"out", "setup", "lidar", "icp", "duration", "seed"},
                                    1,
                                    {"out"}},
                                   argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs* args = &std::get<CliArgs>(parsed);
  const std::filesystem::path source = args->positional()[0];
  const std::filesystem::path out_dir = *args->Option("out");
  const bool quiet = args->Flag("quiet");
  const bool simulate = std::filesystem::is_regular_file(source);
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    if (simulate && args->Option("setup")) {
      throw std::invalid_argument("--setup: only with a LOG (a scenario names its own setup)");
    }
    if (!simulate && (args->Option("duration") || args->Option("seed"))) {
      throw std::invalid_argument("--duration/--seed: only with a SCENARIO.yaml");
    }
    est::LidarOdometryOptions odometry_options;
    const std::string icp = args->Option("icp").value_or("projected");
    if (icp == "point-to-point") {
      odometry_options.icp.metric = est::IcpMetric::kPointToPoint;
    } else if (icp != "projected") {
      throw std::invalid_argument("--icp: expected 'projected' or 'point-to-point', got '" + icp +
                                  "'");
    }
    std::filesystem::create_directories(out_dir);

    // The measurement source and the sensor setup.
    std::unique_ptr<sim::SensorRun> run;
    std::unique_ptr<sensors::LogReader> reader;
    est::EstimatorSensorSetup setup;
    std::vector<TruthSample> truth;
    std::string label;
    double end_s = 0.0;
    if (simulate) {
      const sim::Scenario scenario = LoadScenarioWithOverrides(*args);
      if (!quiet) {
        std::fprintf(stderr,
                     "odometry: %s: building network, running SUMO, building the world...\n",
                     scenario.name.c_str());
      }
      run = std::make_unique<sim::SensorRun>(scenario, out_dir);
      setup = est::ParseEstimatorSensorSetup(YamlNode::LoadString(
          run->sensors().setup_yaml,
          run->sensors().setup.source.empty() ? "sensor setup" : run->sensors().setup.source));
      run->SetTruthObserver([&truth](const TruthSample& s) { truth.push_back(s); });
      label = scenario.name;
      end_s = ToSeconds(run->truth().end_ns());
    } else {
      reader = std::make_unique<sensors::LogReader>(source);
      setup = est::LoadEstimatorSensorSetup(SetupFileOf(*args, *reader, source));
      if (reader->manifest().truth_csv) {
        truth = ReadTruthCsv(source / *reader->manifest().truth_csv).samples;
      }
      label = source.filename().string();
      if (!truth.empty()) end_s = ToSeconds(truth.back().t_ns);
    }
    SE3 T_body_ref;
    const std::vector<est::LidarMount> mounts =
        SelectLidars(setup, args->Option("lidar"), &T_body_ref);
    std::string lidar_names;
    for (const auto& m : mounts) lidar_names += (lidar_names.empty() ? "" : "+") + m.id;

    OdometryRun odometry(mounts, odometry_options, out_dir);
    ProgressBar bar("odometry " + label);
    while (const auto m = run ? run->Next() : reader->Next()) {
      const auto* scan = std::get_if<LidarScan>(&*m);
      if (scan == nullptr) continue;
      const std::optional<TimeNs> t = odometry.Add(*scan);
      if (t && !quiet && end_s > 0.0) {
        char detail[96];
        std::snprintf(detail, sizeof(detail), "t=%.0f s, %zu scans", ToSeconds(*t),
                      odometry.accepted);
        bar.Update(ToSeconds(*t) / end_s, detail);
      }
    }
    odometry.Finish();
    if (!quiet && end_s > 0.0) bar.Finish();
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    const std::vector<reports::ReferenceState> reference =
        truth.empty() ? std::vector<reports::ReferenceState>{}
                      : reports::ReferenceFromTruth(truth, T_body_ref);
    const std::vector<StateEstimate> estimates = ToWorld(odometry.poses(), reference);
    {
      std::ofstream tum(out_dir / "odometry.tum");
      std::ofstream truth_tum;
      if (!reference.empty()) truth_tum.open(out_dir / "truth.tum");
      for (const StateEstimate& e : estimates) {
        WriteTum(tum, e.state.t_ns, SE3(e.state.q_world_imu, e.state.p_world));
        if (reference.empty()) continue;
        if (const auto ref = reports::InterpolateReference(reference, e.state.t_ns)) {
          WriteTum(truth_tum, e.state.t_ns, ref->T_world_frame);
        }
      }
    }
    const std::size_t scans = odometry.scans, accepted = odometry.accepted;
    const double ms_per_scan = scans ? 1e3 * odometry.register_s / static_cast<double>(scans) : 0.0;
    nlohmann::json diag = {
        {"lidars", lidar_names},
        {"scans", scans},
        {"accepted", accepted},
        {"rejected", odometry.rejected},
        {"degenerate", odometry.degenerate},
        {"mean_points_in", scans ? odometry.points_in / scans : 0.0},
        {"mean_points_registered", accepted ? odometry.points_registered / accepted : 0.0},
        {"mean_iterations", accepted ? odometry.iterations / accepted : 0.0},
        {"icp", icp},
        {"register_ms_mean", ms_per_scan},
        {"wall_time_s", wall_s}};
    if (const auto& merger = odometry.merger()) {
      const est::LidarScanMergerDiagnostics& d = merger->diagnostics();
      diag["merger"] = {{"scans_in", d.scans_in},
                        {"merged", d.merged},
                        {"incomplete", d.incomplete},
                        {"late", d.late},
                        {"duplicates", d.duplicates},
                        {"scans_per_lidar", d.scans_per_lidar},
                        {"missing_per_lidar", d.missing_per_lidar}};
    }
    std::ofstream(out_dir / "diagnostics.json") << diag.dump(2) << "\n";

    std::printf("odometry %s, %s (%s): %zu/%zu scans accepted, %zu degenerate, wall %.1f s -> %s\n",
                label.c_str(), lidar_names.c_str(), icp.c_str(), accepted, scans,
                odometry.degenerate, wall_s, out_dir.string().c_str());
    if (!reference.empty()) {
      const reports::TrajectoryMetrics metrics =
          reports::ComputeTrajectoryMetrics(estimates, reference, {});
      const auto [odometry_m, truth_m] = TravelledDistances(estimates, reference);
      const double ratio = truth_m > 0.0 ? odometry_m / truth_m : 0.0;
      nlohmann::json j = reports::ToJson(metrics);
      j["lidars"] = lidar_names;
      j["source"] = source.string();
      j["odometry_distance_m"] = odometry_m;
      j["true_distance_m"] = truth_m;
      j["distance_ratio"] = ratio;
      j["register_ms_mean"] = ms_per_scan;
      j["degenerate_scans"] = odometry.degenerate;
      j["scans"] = scans;
      std::ofstream(out_dir / "metrics.json") << j.dump(2) << "\n";
      std::printf("%12s %15s %9s %9s %10s %9s %8s %10s\n", "KITTI t [%]", "KITTI r [deg/m]",
                  "segments", "APE [m]", "dist [m]", "odo/true", "ms/scan", "degenerate");
      std::printf("%12.3f %15.5f %9zu %9.3f %10.1f %9.5f %8.2f %10zu\n",
                  metrics.kitti_translation_percent, metrics.kitti_rotation_deg_per_m,
                  metrics.kitti_segments, metrics.ape_translation_m.rmse, truth_m, ratio,
                  ms_per_scan, odometry.degenerate);
    }
    if (reader && reader->error()) {
      std::fprintf(stderr, "error: %s\n", reader->error()->c_str());
      return 2;
    }
    return 0;
  } catch (...) {
    return ExitCodeForCurrentException("odometry");
  }
}

}  // namespace statebench::app
