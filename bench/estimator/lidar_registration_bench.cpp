// Lidar registration cost and accuracy (issue 5): our odometry step and our ICP next to PCL 1.13's
// ICP, GICP and NDT, on the same simulated scan pairs of a Hesai XT32 and a Velodyne VLP-16.
//
// Data (deterministic): a 5 x 5 town grid (120 m blocks, dense buildings, kerbs, poles, trees,
// parked cars, oncoming and crossing traffic) as in bench/sensors/lidar_raycast_bench. The lidar
// sits 1.9 m above the road on a car driving east at 8-12 m/s (10 + 2 sin(0.5 t)) weaving +-0.5 m
// across its lane, following the terrain's slope (pitch and roll). kScans consecutive 10 Hz sweeps
// per lidar are ray cast with the sensor's error model (XT32: 1 cm range noise, 80 m at 10 %
// reflectivity; VLP-16: 3 cm); a scan's stamp is its first column, truth T_world_lidar at the
// stamps gives T_prev_curr = T_world_lidar(k-1)^-1 T_world_lidar(k).
//
// BM_OdometryStep: LidarOdometry::RegisterScan on the raw, motion-distorted sweeps (the odometry
// deskews them itself with its constant-velocity model); the first kWarmupScans build the map,
// each of the next ones is one timed iteration (filter, deskew, downsample, ICP, map update).
// Errors: T_prev_curr of every timed scan against truth, and the pose at the last scan.
//
// BM_Pair*: one scan registered against the previous one, both deskewed with the TRUE motion so
// that only registration is compared. Every method gets the same points: the source is the
// current scan voxel-subsampled like the odometry's registration set (first point per 0.5 m cube,
// then per 1.5 m cube), the target the previous scan subsampled at 0.5 m (the odometry's map
// density); the counts are the src_pts / tgt_pts counters. Per pair, the timed work is
// everything from those point lists to the estimate: target structure (our voxel hash map, PCL's
// k-d tree, GICP's covariances, NDT's cells) and the registration. Initial guess (same for all
// methods): identity (guess=0, ~1 m and up to 2.5 deg away) or constant velocity (guess=1, the
// true motion of the previous pair, a few cm away). Max correspondence distance: 2.0 m from
// identity, 1.0 m from constant velocity, for our ICP (Geman-McClure scale = distance / 9, the
// odometry's 3 sigma / (sigma / 3)) and PCL ICP/GICP; at most 50 iterations for PCL (ours stops
// at |dx| < 1e-4); PCL ICP translation epsilon 1e-8 m^2, GICP translation and rotation epsilon
// 1e-4 (20 neighbours per covariance), NDT resolution 1.0 m, step 0.1, epsilon 1e-8 m^2. NDT's
// target is the whole previous scan (truth-deskewed, range-filtered): at 0.5 m subsampling a
// 1 m cell holds too few points for PCL's covariance (at least 6), most cells drop out and NDT
// drifts off. PCL 1.13's registration is single-threaded, so it runs on one thread only. The
// "initial guess" rows give the error of the guess itself (no registration).
//
// Errors against truth: E = T_true^-1 T_est, t_err = |t(E)|, r_err = |Log R(E)|, RMS and max over
// the pairs or scans; fwd_bias = mean of (t_est - t_true) . t_true / |t_true| (negative: forward
// motion under-estimated). Times per scan: ms/scan is wall time (inflated when the machine is
// shared: the load average is printed); cpu_ms is the process CPU time summed over threads (the
// work, whatever the load); main_ms is the CPU time of the calling thread, which takes part in
// the TBB work, so that on an idle machine it approximates the wall time (with one thread it
// equals cpu_ms).
// The program prints a summary table after the Google Benchmark output.
#include <benchmark/benchmark.h>
#include <oneapi/tbb/global_control.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bench/dense_town.hpp"
#include "core/se3.hpp"
#include "core/so3.hpp"
#include "estimator/icp_registration.hpp"
#include "estimator/lidar_odometry.hpp"
#include "estimator/lidar_preprocessing.hpp"
#include "estimator/voxel_hash_map.hpp"
#include "sensors/lidar_simulator.hpp"
#include "sensors/synthetic_roads.hpp"

namespace statebench {
namespace {

constexpr int kScans = 50;        // per lidar: 5 s, ~50 m
constexpr int kWarmupScans = 10;  // odometry: untimed, builds the map
constexpr int kPairStride = 2;    // pairs (k-1, k) for k = 2, 4, ..., kScans - 2
constexpr TimeNs kPeriodNs = 100'000'000;
constexpr double kLidarHeightM = 1.9;
constexpr double kLaneY = 120.0 - 5.25;

const char* const kLidarModels[] = {"hesai_xt32", "velodyne_vlp16"};
const char* const kLidarNames[] = {"XT32", "VLP-16"};

using bench::DenseTownTerrain;

// True lidar pose: heading along the velocity, body z along the terrain normal.
SE3 TrueLidarPose(TimeNs t_ns) {
  const double t = ToSeconds(t_ns);
  const double x = 200.0 + 10.0 * t + 4.0 * (1.0 - std::cos(0.5 * t));
  const double vx = 10.0 + 2.0 * std::sin(0.5 * t);
  const double y = kLaneY + 0.5 * std::sin(0.8 * t);
  const double vy = 0.4 * std::cos(0.8 * t);
  const double hx = 0.01, hy = 0.008 * std::cos(0.004 * y);  // terrain gradient
  const Vec3 z_b = Vec3(-hx, -hy, 1.0).normalized();
  const Vec3 heading(vx, vy, hx * vx + hy * vy);
  const Vec3 y_b = z_b.cross(heading).normalized();
  Mat3 R;
  R << y_b.cross(z_b), y_b, z_b;
  return SE3(Quat(R), Vec3(x, y, DenseTownTerrain(x, y) + kLidarHeightM));
}

double CpuSeconds(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Town {
  std::unique_ptr<sensors::LidarWorld> world;

  Town() {
    using namespace sensors;
    const RoadGeometry roads = bench::DenseTownRoads();
    world = bench::BuildDenseTown(roads);
    // Traffic on every third lane at 8-14 m/s, leaving out vehicles that would come within 6 m
    // of our car (it is not part of the traffic).
    constexpr int kFrames = 70;  // 7 s of 100 ms steps
    std::vector<TrafficFrame> frames(kFrames + 1);
    for (int k = 0; k <= kFrames; ++k) frames[k].t_ns = TimeNs{k} * kPeriodNs;
    for (std::size_t lane = 0; lane < roads.lanes.size(); lane += 3) {
      const auto& c = roads.lanes[lane].centre;
      const Vec3 dir = (c.back() - c.front()).normalized();
      const double speed = 8.0 + static_cast<double>(lane % 7);
      std::vector<TrafficBox> track;
      bool clear = true;
      for (int k = 0; k <= kFrames && clear; ++k) {
        TrafficBox box;
        box.id = "veh" + std::to_string(lane);
        box.centre_world = c.front() + (10.0 + 0.1 * k * speed) * dir + Vec3(0.0, 0.0, 0.75);
        box.yaw_rad = std::atan2(dir.y(), dir.x());
        const Vec3 ego = TrueLidarPose(frames[k].t_ns).translation();
        clear = (box.centre_world - ego).head<2>().norm() > 6.0;
        track.push_back(box);
      }
      if (!clear) continue;
      for (int k = 0; k <= kFrames; ++k) frames[k].boxes.push_back(track[k]);
    }
    world->SetTraffic(sensors::TrafficTimeline(frames));
  }
};

const Town& TheTown() {
  static const Town town;
  return town;
}

// One registration problem: source (current scan) into target (previous scan) frame.
struct ScanPair {
  std::vector<Vec3> source;
  std::vector<Vec3> target;
  std::vector<Vec3> dense_target;  // the previous scan, truth-deskewed, not subsampled (NDT)
  SE3 truth;                       // T_prev_curr
  SE3 cv_guess;                    // true motion of the previous pair
};

struct LidarSequence {
  std::vector<LidarScan> scans;  // raw sweeps, motion-distorted
  std::vector<SE3> T_world_lidar;
  std::vector<ScanPair> pairs;
  double points_per_scan = 0.0;
};

LidarSequence MakeSequence(int lidar) {
  sensors::LidarModelValues values;
  values.model = kLidarModels[lidar];
  values.sensor_id = "roof";
  const sensors::LidarSimulator simulator(*TheTown().world,
                                          sensors::MakeLidarModelParams(values, "bench"), 7);
  const est::LidarOdometryOptions odo;
  LidarSequence seq;
  std::vector<std::vector<Vec3>> deskewed;  // truth-deskewed, range-filtered
  std::vector<std::vector<Vec3>> frames;    // the same, 0.5 m subsample
  for (int k = 0; k < kScans; ++k) {
    const TimeNs stamp_ns = TimeNs{k} * kPeriodNs;
    seq.scans.push_back(simulator.SimulateScan(TrueLidarPose, stamp_ns, k));
    seq.T_world_lidar.push_back(TrueLidarPose(stamp_ns));
    seq.points_per_scan += static_cast<double>(seq.scans.back().points->size()) / kScans;
    const SE3 T_lidar_world = seq.T_world_lidar.back().Inverse();
    const est::SweepMotion truth_sweep = [&](double t_s) {
      return T_lidar_world * TrueLidarPose(stamp_ns + FromSeconds(t_s));
    };
    est::LidarFilterStats stats;
    const auto timed = est::FilterScanPoints(
        *seq.scans.back().points, {.min_range_m = odo.min_range_m, .max_range_m = odo.max_range_m},
        &stats);
    deskewed.push_back(est::DeskewPoints(timed, truth_sweep));
    frames.push_back(
        est::VoxelDownsample(deskewed.back(), odo.map_downsample_factor * odo.voxel_size_m));
  }
  for (int k = 2; k < kScans; k += kPairStride) {
    ScanPair pair;
    pair.source =
        est::VoxelDownsample(frames[k], odo.register_downsample_factor * odo.voxel_size_m);
    pair.target = frames[k - 1];
    pair.dense_target = deskewed[k - 1];
    pair.truth = seq.T_world_lidar[k - 1].Inverse() * seq.T_world_lidar[k];
    pair.cv_guess = seq.T_world_lidar[k - 2].Inverse() * seq.T_world_lidar[k - 1];
    seq.pairs.push_back(std::move(pair));
  }
  return seq;
}

const LidarSequence& Sequence(int lidar) {
  static const LidarSequence sequences[] = {MakeSequence(0), MakeSequence(1)};
  return sequences[lidar];
}

// Error statistics of estimates against truth.
struct ErrorStats {
  double t_sse = 0.0, r_sse = 0.0, t_max = 0.0, r_max = 0.0, fwd_sum = 0.0;
  int count = 0, failed = 0;

  void Add(const SE3& estimate, const SE3& truth) {
    const SE3 E = truth.Inverse() * estimate;
    const double t_err = E.translation().norm();
    const double r_err = so3::Log(E.rotation()).norm();
    t_sse += t_err * t_err;
    r_sse += r_err * r_err;
    t_max = std::max(t_max, t_err);
    r_max = std::max(r_max, r_err);
    fwd_sum += (estimate.translation() - truth.translation()).dot(truth.translation().normalized());
    ++count;
  }
  double TRmsMm() const { return count ? 1e3 * std::sqrt(t_sse / count) : NAN; }
  double RRmsMdeg() const { return count ? 1e3 * std::sqrt(r_sse / count) * 180.0 / M_PI : NAN; }
  double TMaxMm() const { return 1e3 * t_max; }
  double RMaxMdeg() const { return 1e3 * r_max * 180.0 / M_PI; }
  double FwdBiasMm() const { return count ? 1e3 * fwd_sum / count : NAN; }
};

// One line of the closing table.
struct Row {
  std::string method, lidar, guess;
  int threads = 1;
  double wall_ms = 0.0, cpu_ms = 0.0, main_ms = 0.0;
  ErrorStats errors;
  double src_pts = 0.0, tgt_pts = 0.0;
  std::string extra;
};
std::vector<Row>& Rows() {
  static std::vector<Row> rows;
  return rows;
}

void SetErrorCounters(benchmark::State& state, const ErrorStats& e) {
  state.counters["t_err_rms_mm"] = e.TRmsMm();
  state.counters["t_err_max_mm"] = e.TMaxMm();
  state.counters["r_err_rms_mdeg"] = e.RRmsMdeg();
  state.counters["r_err_max_mdeg"] = e.RMaxMdeg();
  state.counters["fwd_bias_mm"] = e.FwdBiasMm();
  state.counters["failed"] = e.failed;
}

// Times the loop body per iteration: wall, process CPU and calling-thread CPU.
class ScanClock {
 public:
  ScanClock()
      : wall_(std::chrono::steady_clock::now()),
        cpu_(CpuSeconds(CLOCK_PROCESS_CPUTIME_ID)),
        main_(CpuSeconds(CLOCK_THREAD_CPUTIME_ID)) {}
  void Finish(benchmark::State& state, Row* row) const {
    const double n = static_cast<double>(state.iterations());
    row->wall_ms =
        1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_).count() / n;
    row->cpu_ms = 1e3 * (CpuSeconds(CLOCK_PROCESS_CPUTIME_ID) - cpu_) / n;
    row->main_ms = 1e3 * (CpuSeconds(CLOCK_THREAD_CPUTIME_ID) - main_) / n;
    state.counters["cpu_ms"] = row->cpu_ms;
    state.counters["main_ms"] = row->main_ms;
  }

 private:
  std::chrono::steady_clock::time_point wall_;
  double cpu_;
  double main_;
};

// ---- Our full odometry step ---------------------------------------------------------------

// FNV-1a digest of the bits of every odometry result (pose, covariance, diagnostics): equal
// digests before and after a change to the registration mean identical registrations.
class ResultDigest {
 public:
  void Add(const est::LidarOdometryResult& r) {
    Bytes(r.accepted);
    Bytes(r.first_scan);
    Bytes(r.T_prev_curr.rotation().coeffs());
    Bytes(r.T_prev_curr.translation());
    Bytes(r.T_world_lidar.rotation().coeffs());
    Bytes(r.T_world_lidar.translation());
    Bytes(r.covariance);
    const est::LidarOdometryDiagnostics& d = r.diagnostics;
    Bytes(d.points_kept);
    Bytes(d.points_registered);
    Bytes(d.iterations);
    Bytes(d.correspondences);
    Bytes(d.degenerate_directions);
    Bytes(d.information_eigenvalues);
    Bytes(d.weakest_direction);
    Bytes(d.threshold_m);
    Bytes(d.residual_sigma_m);
  }
  void Add(const SE3& T) {
    Bytes(T.rotation().coeffs());
    Bytes(T.translation());
  }
  std::uint64_t value() const { return hash_; }

 private:
  template <typename T>
  void Bytes(const T& value) {
    if constexpr (requires { value.data(); value.size(); }) {
      for (Eigen::Index i = 0; i < value.size(); ++i) Bytes(value.data()[i]);
    } else {
      unsigned char raw[sizeof(T)];
      std::memcpy(raw, &value, sizeof(T));
      for (const unsigned char c : raw) hash_ = (hash_ ^ c) * 1099511628211ull;
    }
  }
  std::uint64_t hash_ = 14695981039346656037ull;
};

void BM_OdometryStep(benchmark::State& state) {
  const int lidar = static_cast<int>(state.range(0));
  const auto threads = static_cast<std::size_t>(state.range(1));
  const LidarSequence& seq = Sequence(lidar);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  est::LidarOdometry odometry({});
  ResultDigest digest;
  for (int k = 0; k < kWarmupScans; ++k) digest.Add(odometry.RegisterScan(seq.scans[k]));
  std::vector<est::LidarOdometryResult> results;
  results.reserve(kScans);
  int k = kWarmupScans;
  Row row;
  const ScanClock clock;
  for (auto _ : state) {
    results.push_back(odometry.RegisterScan(seq.scans[k]));
    ++k;
  }
  clock.Finish(state, &row);
  double registered = 0.0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const est::LidarOdometryResult& r = results[i];
    const int scan = kWarmupScans + static_cast<int>(i);
    digest.Add(r);
    registered += static_cast<double>(r.diagnostics.points_registered) / results.size();
    if (!r.accepted) {
      ++row.errors.failed;
      continue;
    }
    row.errors.Add(r.T_prev_curr, seq.T_world_lidar[scan - 1].Inverse() * seq.T_world_lidar[scan]);
  }
  // The target of the last registration: the local map.
  row.tgt_pts = static_cast<double>(odometry.local_map().Points().size());
  // Pose of the last scan in the odometry frame (lidar at scan 0) against truth.
  const SE3 truth_end = seq.T_world_lidar.front().Inverse() * seq.T_world_lidar[k - 1];
  const SE3 end_error = truth_end.Inverse() * odometry.T_world_lidar();
  const double distance = truth_end.translation().norm();
  SetErrorCounters(state, row.errors);
  state.counters["src_pts"] = registered;
  state.counters["raw_pts"] = seq.points_per_scan;
  state.counters["tgt_pts"] = row.tgt_pts;
  state.counters["end_err_pct"] = 100.0 * end_error.translation().norm() / distance;
  row.method = "odometry step";
  row.lidar = kLidarNames[lidar];
  row.guess = "own cv";
  row.threads = static_cast<int>(threads);
  row.src_pts = registered;
  char extra[128];
  std::snprintf(extra, sizeof(extra), "raw %.0f pts, end %.3f %% of %.1f m, digest %016llx",
                seq.points_per_scan, 100.0 * end_error.translation().norm() / distance, distance,
                static_cast<unsigned long long>(digest.value()));
  row.extra = extra;
  Rows().push_back(row);
}
BENCHMARK(BM_OdometryStep)
    ->ArgsProduct({{0, 1}, {1, 2}})
    ->ArgNames({"lidar", "threads"})
    ->Iterations(kScans - kWarmupScans)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// ---- Pairwise registration ----------------------------------------------------------------

double MaxCorrespondenceM(bool cv_guess) { return cv_guess ? 1.0 : 2.0; }

// A registration of source points into the target's frame from an initial guess.
using RegisterFn = std::optional<SE3> (*)(const std::vector<Vec3>& source,
                                          const std::vector<Vec3>& target, const SE3& guess,
                                          double max_corr_m);

// The guess itself: the error of not registering at all.
std::optional<SE3> InitialGuessOnly(const std::vector<Vec3>&, const std::vector<Vec3>&,
                                    const SE3& guess, double) {
  return guess;
}

std::optional<SE3> RegisterOurs(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                                const SE3& guess, double max_corr_m) {
  est::VoxelHashMap map({.voxel_size_m = 1.0, .max_points_per_voxel = 20, .max_range_m = 100.0});
  map.AddPoints(target);
  const est::IcpResult icp =
      est::RegisterScanToMap(source, map, guess, max_corr_m, max_corr_m / 9.0, {});
  if (!icp.ok) return std::nullopt;
  return icp.T_map_scan;
}

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

Cloud::Ptr ToCloud(const std::vector<Vec3>& points) {
  auto cloud = std::make_shared<Cloud>();
  cloud->reserve(points.size());
  for (const Vec3& p : points) {
    cloud->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                   static_cast<float>(p.z())));
  }
  return cloud;
}

SE3 FromMatrix(const Eigen::Matrix4f& T) {
  const Eigen::Matrix4d Td = T.cast<double>();
  // Re-orthonormalise the float rotation.
  return SE3(Quat(Mat3(Td.topLeftCorner<3, 3>())).normalized(), Vec3(Td.topRightCorner<3, 1>()));
}

template <typename Registration>
std::optional<SE3> AlignWithPcl(Registration& reg, const std::vector<Vec3>& source,
                                const std::vector<Vec3>& target, const SE3& guess) {
  reg.setInputSource(ToCloud(source));
  reg.setInputTarget(ToCloud(target));
  Eigen::Matrix4f T_guess = Eigen::Matrix4f::Identity();
  T_guess.topLeftCorner<3, 3>() = guess.rotation().toRotationMatrix().cast<float>();
  T_guess.topRightCorner<3, 1>() = guess.translation().cast<float>();
  Cloud aligned;
  reg.align(aligned, T_guess);
  if (!reg.hasConverged()) return std::nullopt;
  return FromMatrix(reg.getFinalTransformation());
}

std::optional<SE3> RegisterPclIcp(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                                  const SE3& guess, double max_corr_m) {
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  icp.setMaxCorrespondenceDistance(max_corr_m);
  icp.setMaximumIterations(50);
  icp.setTransformationEpsilon(1e-8);
  return AlignWithPcl(icp, source, target, guess);
}

std::optional<SE3> RegisterPclGicp(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                                   const SE3& guess, double max_corr_m) {
  pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp;
  gicp.setMaxCorrespondenceDistance(max_corr_m);
  gicp.setMaximumIterations(50);
  gicp.setTransformationEpsilon(1e-4);
  gicp.setRotationEpsilon(1e-4);
  return AlignWithPcl(gicp, source, target, guess);
}

std::optional<SE3> RegisterPclNdt(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                                  const SE3& guess, double /*max_corr_m*/) {
  pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt;
  ndt.setResolution(1.0f);
  ndt.setStepSize(0.1);
  ndt.setMaximumIterations(50);
  ndt.setTransformationEpsilon(1e-8);
  return AlignWithPcl(ndt, source, target, guess);
}

enum class Target { kSubsampled, kDense };

void RunPairs(benchmark::State& state, const char* method, RegisterFn register_pair,
              Target target = Target::kSubsampled) {
  const int lidar = static_cast<int>(state.range(0));
  const auto threads = static_cast<std::size_t>(state.range(1));
  const bool cv_guess = state.range(2) != 0;
  const LidarSequence& seq = Sequence(lidar);
  tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
  const double max_corr_m = MaxCorrespondenceM(cv_guess);
  std::vector<std::optional<SE3>> estimates;
  estimates.reserve(seq.pairs.size());
  std::size_t i = 0;
  Row row;
  const ScanClock clock;
  for (auto _ : state) {
    const ScanPair& pair = seq.pairs[i % seq.pairs.size()];
    estimates.push_back(register_pair(pair.source,
                                      target == Target::kDense ? pair.dense_target : pair.target,
                                      cv_guess ? pair.cv_guess : SE3(), max_corr_m));
    ++i;
  }
  clock.Finish(state, &row);
  ResultDigest digest;
  for (std::size_t j = 0; j < estimates.size(); ++j) {
    const ScanPair& pair = seq.pairs[j % seq.pairs.size()];
    if (estimates[j]) {
      digest.Add(*estimates[j]);
      row.errors.Add(*estimates[j], pair.truth);
    } else {
      ++row.errors.failed;
    }
    row.src_pts += static_cast<double>(pair.source.size()) / estimates.size();
    row.tgt_pts += static_cast<double>(target == Target::kDense ? pair.dense_target.size()
                                                                : pair.target.size()) /
                   estimates.size();
  }
  SetErrorCounters(state, row.errors);
  state.counters["src_pts"] = row.src_pts;
  state.counters["tgt_pts"] = row.tgt_pts;
  row.method = method;
  row.lidar = kLidarNames[lidar];
  row.guess = cv_guess ? "cv" : "identity";
  char extra[32];
  std::snprintf(extra, sizeof(extra), "digest %016llx",
                static_cast<unsigned long long>(digest.value()));
  row.extra = extra;
  row.threads = static_cast<int>(threads);
  Rows().push_back(row);
}

void BM_PairInitialGuess(benchmark::State& state) {
  RunPairs(state, "initial guess", InitialGuessOnly);
}
void BM_PairOurIcp(benchmark::State& state) { RunPairs(state, "our ICP", RegisterOurs); }
void BM_PairPclIcp(benchmark::State& state) { RunPairs(state, "PCL ICP", RegisterPclIcp); }
void BM_PairPclGicp(benchmark::State& state) { RunPairs(state, "PCL GICP", RegisterPclGicp); }
void BM_PairPclNdt(benchmark::State& state) {
  RunPairs(state, "PCL NDT", RegisterPclNdt, Target::kDense);
}

constexpr int kPairs = (kScans - 2 + kPairStride - 1) / kPairStride;

BENCHMARK(BM_PairInitialGuess)
    ->ArgsProduct({{0, 1}, {1}, {0, 1}})
    ->ArgNames({"lidar", "threads", "guess"})
    ->Iterations(kPairs)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_PairOurIcp)
    ->ArgsProduct({{0, 1}, {1, 2}, {0, 1}})
    ->ArgNames({"lidar", "threads", "guess"})
    ->Iterations(kPairs)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_PairPclIcp)
    ->ArgsProduct({{0, 1}, {1}, {0, 1}})
    ->ArgNames({"lidar", "threads", "guess"})
    ->Iterations(kPairs)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_PairPclGicp)
    ->ArgsProduct({{0, 1}, {1}, {0, 1}})
    ->ArgNames({"lidar", "threads", "guess"})
    ->Iterations(kPairs)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_PairPclNdt)
    ->ArgsProduct({{0, 1}, {1}, {0, 1}})
    ->ArgNames({"lidar", "threads", "guess"})
    ->Iterations(kPairs)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void PrintTable() {
  if (Rows().empty()) return;
  double load[3] = {0.0, 0.0, 0.0};
  getloadavg(load, 3);
  std::printf("\nload average at the end: %.2f %.2f %.2f (1, 5, 15 min) on %u hardware threads",
              load[0], load[1], load[2], std::thread::hardware_concurrency());
  std::printf("\n%-14s %-7s %-8s %3s %8s %7s %7s %7s %7s %8s %8s %9s %9s %8s %6s  %s\n", "method",
              "lidar", "guess", "thr", "ms/scan", "cpu_ms", "main_ms", "src_pts", "tgt_pts",
              "t_rms_mm", "t_max_mm", "r_rms_mdg", "r_max_mdg", "fwd_b_mm", "failed", "");
  for (const Row& r : Rows()) {
    std::printf(
        "%-14s %-7s %-8s %3d %8.2f %7.2f %7.2f %7.0f %7.0f %8.2f %8.2f %9.2f %9.2f %8.2f %6d  "
        "%s\n",
        r.method.c_str(), r.lidar.c_str(), r.guess.c_str(), r.threads, r.wall_ms, r.cpu_ms,
        r.main_ms, r.src_pts, r.tgt_pts, r.errors.TRmsMm(), r.errors.TMaxMm(), r.errors.RRmsMdeg(),
        r.errors.RMaxMdeg(), r.errors.FwdBiasMm(), r.errors.failed, r.extra.c_str());
  }
}

}  // namespace
}  // namespace statebench

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  statebench::PrintTable();
  benchmark::Shutdown();
  return 0;
}
