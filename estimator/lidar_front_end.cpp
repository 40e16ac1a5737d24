#include "estimator/lidar_front_end.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/so3.hpp"
#include "core/stage_profile.hpp"
#include "estimator/sqrt_information.hpp"

namespace statebench::est {
namespace {

TimeNs SweepEnd(const LidarScan& scan) {
  float t_max = 0.f;
  for (const LidarPoint& p : *scan.points) {
    if (std::isfinite(p.t)) t_max = std::max(t_max, p.t);
  }
  return scan.header.stamp_ns + FromSeconds(std::min(0.5, static_cast<double>(t_max)));
}

}  // namespace

LidarFrontEnd::LidarFrontEnd(const EstimatorSensorSetup& setup,
                             std::vector<const EstimatorSensor*> lidars,
                             const FactorGraphOptions& options, FrontEndContext& ctx,
                             LidarOdometryPool* pool)
    : setup_(setup), lidars_(std::move(lidars)), options_(options), ctx_(ctx) {
  if (lidars_.empty()) return;
  std::vector<LidarMount> mounts;  // in the first lidar's frame
  const SE3 T_ref_imu = lidars_.front()->T_imu_sensor.Inverse();
  for (const EstimatorSensor* l : lidars_) {
    mounts.push_back({l->id, T_ref_imu * l->T_imu_sensor});
  }
  if (options.lidar.motion_prior != LidarPriorSource::kImu) {
    LidarSetKey key;
    for (const LidarMount& m : mounts) key.mounts.emplace_back(m.id, m.T_ref_lidar);
    char intake[160];
    std::snprintf(intake, sizeof intake, "reorder %.17g s, imu limits %.17g %.17g %.17g",
                  options.ReorderLatency(setup), options.imu_limits.max_accel_mps2,
                  options.imu_limits.max_gyro_radps, options.imu_limits.max_gap_s);
    key.intake = intake;
    std::optional<Quat> q_imu_lidar;
    if (options.lidar.motion_prior == LidarPriorSource::kGyro) {
      q_imu_lidar = lidars_.front()->T_imu_sensor.rotation();
      gyro_.emplace();
    }
    shared_ = pool != nullptr
                  ? pool->For(key, q_imu_lidar, options.lidar.odometry)
                  : std::make_shared<SharedLidarOdometry>(options.lidar.odometry, q_imu_lidar);
  } else {
    odometry_.emplace(options.lidar.odometry);
  }
  if (lidars_.size() > 1) {
    // Several lidars: one merged scan per period in the first lidar's frame.
    LidarScanMergerOptions merge;
    merge.merged_id = lidars_.front()->id;
    merger_.emplace(std::move(mounts), merge);
  }
}

void LidarFrontEnd::OnImu(const ImuSample& sample) {
  if (!gyro_) return;
  gyro_->Add(sample.header.stamp_ns, sample.gyro);
  // The gyro prior reaches back to the previous registered scan: two seconds cover a few
  // rejected ones (beyond, the odometry's constant velocity alone, for every estimator alike).
  gyro_->DropBefore(sample.header.stamp_ns - FromSeconds(2.0));
}

void LidarFrontEnd::OnRestart() {
  last_scan_ns_.reset();
  if (shared_) {
    // The shared odometry goes on (its scans keep coming); no factor reaches into the old window.
    restart_ns_ = ctx_.newest_imu_ns;
    return;
  }
  if (odometry_) odometry_.emplace(options_.lidar.odometry);
  waiting_.clear();
}

Claim LidarFrontEnd::Claims(const Measurement& m) const {
  if (!std::holds_alternative<LidarScan>(m)) return Claim::kOtherKind;
  const std::string& id = HeaderOf(m).sensor_id;
  const EstimatorSensor* s = setup_.Find(id);
  if (s == nullptr || s->kind != SensorKind::kLidar) return Claim::kUnknownSensor;
  return lidars_.empty() || Used(id) ? Claim::kTaken : Claim::kOtherKind;
}

bool LidarFrontEnd::Used(const std::string& id) const {
  return std::any_of(lidars_.begin(), lidars_.end(),
                     [&](const EstimatorSensor* l) { return l->id == id; });
}

void LidarFrontEnd::Process(const Measurement& m) {
  const LidarScan& scan = std::get<LidarScan>(m);
  const std::string& id = scan.header.sensor_id;
  if (!Used(id)) return ctx_.Reject(id, scan.header.stamp_ns, RejectReason::kDisabled);
  if (!ctx_.initialized) {
    ctx_.Reject(id, scan.header.stamp_ns, RejectReason::kNotInitialized);
    if (!shared_) return;  // a shared odometry registers every scan (the factors wait)
  }
  if (!merger_) {
    waiting_.push_back({scan, SweepEnd(scan)});
  } else {
    // Several lidars: counted here, registered as one merged scan (under the first id).
    if (ctx_.initialized) ctx_.Accept(id, scan.header.stamp_ns);
    for (LidarScan& merged : merger_->Add(scan)) {
      const TimeNs end_ns = SweepEnd(merged);
      waiting_.push_back({std::move(merged), end_ns});
    }
  }
  ProcessWaitingScans();
}

void LidarFrontEnd::ProcessWaitingScans() {
  while (!waiting_.empty()) {
    const TimeNs sweep_end_ns = waiting_.front().sweep_end_ns;
    if (sweep_end_ns > ctx_.newest_imu_ns) return;
    // The gyro prior waits for the released samples to cover the sweep (the same for every
    // estimator sharing the odometry, whatever its reorder latency).
    if (gyro_ && sweep_end_ns > gyro_->newest_ns()) return;
    const LidarScan scan = std::move(waiting_.front().scan);
    waiting_.pop_front();
    RegisterScan(scan, sweep_end_ns);
  }
}

// IMU prior: the lidar's motion since the previous accepted scan and within the sweep (poses
// every 5 ms, interpolated on SE3), from the window or the IMU prediction (mean only).
std::optional<LidarMotionPrior> LidarFrontEnd::MotionPrior(TimeNs t, TimeNs sweep_end_ns,
                                                           std::optional<SE3>* T_w_prev) const {
  const SE3 X = ImuLidar();
  const std::vector<NavState> window = ctx_.smoother.WindowStates();
  const auto pose_at = [&](TimeNs t_ns) -> std::optional<SE3> {
    const auto x = ctx_.output.MeanAt(t_ns, window);
    if (!x) return std::nullopt;
    return SE3(x->q_world_imu, x->p_world);
  };
  const std::optional<SE3> T_w_i = pose_at(t);
  if (last_scan_ns_) *T_w_prev = pose_at(*last_scan_ns_);
  if (!T_w_i) return std::nullopt;
  constexpr TimeNs kStep = 5 * kNsPerMillisecond;
  std::vector<std::pair<double, SE3>> table;
  const SE3 T_l_w = (*T_w_i * X).Inverse();
  for (TimeNs tk = t;; tk = std::min(sweep_end_ns, tk + kStep)) {
    const std::optional<SE3> T = pose_at(tk);
    if (!T) break;
    table.emplace_back(ToSeconds(tk - t), T_l_w * *T * X);
    if (tk == sweep_end_ns) break;
  }
  if (table.empty() || (!*T_w_prev && last_scan_ns_)) return std::nullopt;
  LidarMotionPrior p;
  p.T_prev_curr = *T_w_prev ? (**T_w_prev * X).Inverse() * (*T_w_i * X) : SE3::Identity();
  p.sweep = TabulatedSweepMotion(std::move(table));
  return p;
}

std::optional<SE3> LidarFrontEnd::PredictedMotion(TimeNs from_ns, TimeNs to_ns) const {
  const SE3 X = ImuLidar();
  const std::vector<NavState> window = ctx_.smoother.WindowStates();
  const auto from = ctx_.output.MeanAt(from_ns, window);
  const auto to = ctx_.output.MeanAt(to_ns, window);
  if (!from || !to) return std::nullopt;
  return (SE3(from->q_world_imu, from->p_world) * X).Inverse() *
         (SE3(to->q_world_imu, to->p_world) * X);
}

std::optional<SlidingWindowSmoother::MountCorrection> LidarFrontEnd::MountCorrection() {
  const LidarFactorOptions& o = options_.lidar;
  if (!o.estimate_mount) return std::nullopt;
  return ctx_.MountGlobals(lidars_.front()->id, o.mount_prior_sigma_deg * M_PI / 180.0,
                           o.mount_max_deg * M_PI / 180.0, /*with_roll=*/true);
}

SE3 LidarFrontEnd::ImuLidar() const {
  const EstimatorSensor& lidar = *lidars_.front();
  if (!options_.lidar.estimate_mount) return lidar.T_imu_sensor;
  return SE3(lidar.T_imu_sensor.rotation() * so3::Exp<double>(ctx_.MountEstimate(lidar.id)),
             lidar.T_imu_sensor.translation());
}

// The odometry's result for the scan and, for the gate, the estimator's prediction of the same
// motion when it holds both ends: from this estimator's IMU prior, or beside the shared odometry.
LidarOdometryResult LidarFrontEnd::Registration(const LidarScan& scan, TimeNs sweep_end_ns,
                                                std::optional<SE3>* T_prev_curr_imu) {
  const TimeNs t = scan.header.stamp_ns;
  if (shared_) {
    const LidarOdometryResult r = [&] {
      const StageScope stage(Stage::kLidarOdometry);
      return shared_->Register(scan, sweep_end_ns, gyro_ ? &*gyro_ : nullptr);
    }();
    if (r.accepted && !r.first_scan && ctx_.initialized) {
      *T_prev_curr_imu = PredictedMotion(r.prev_stamp_ns, t);
    }
    return r;
  }
  std::optional<SE3> T_w_prev;
  const std::optional<LidarMotionPrior> prior = MotionPrior(t, sweep_end_ns, &T_w_prev);
  if (prior && T_w_prev) *T_prev_curr_imu = prior->T_prev_curr;
  const StageScope stage(Stage::kLidarOdometry);
  return odometry_->RegisterScan(scan, prior);
}

void LidarFrontEnd::RegisterScan(const LidarScan& scan, TimeNs sweep_end_ns) {
  const EstimatorSensor& lidar = *lidars_.front();
  const std::string& id = lidar.id;
  const TimeNs t = scan.header.stamp_ns;
  std::optional<SE3> T_prev_curr_imu;
  const LidarOdometryResult r = Registration(scan, sweep_end_ns, &T_prev_curr_imu);
  const bool merged = merger_.has_value();  // the input scans were counted already
  if (!ctx_.initialized) {  // a shared odometry's scan before the first state: no factor
    if (r.accepted) ctx_.Count(id, "registered_before_initialization");
    return;
  }
  if (!r.accepted) {
    // The category of the reason (its text before the details in parentheses).
    const std::string reason = r.reject_reason.substr(0, r.reject_reason.find(" ("));
    ctx_.Count(id, reason.empty() ? "registration failed" : reason);
    return ctx_.Reject(id, t, RejectReason::kRegistrationFailed);
  }
  if (r.diagnostics.degenerate) ctx_.Count(id, "degenerate");
  // The first scan of the estimator's window (a shared odometry's previous scan may precede
  // the first state or a restart): it anchors the next factor.
  const bool anchor =
      r.first_scan || (shared_ && (!last_scan_ns_ || r.prev_stamp_ns < restart_ns_));
  last_scan_ns_ = t;
  if (anchor) {
    ctx_.Count(id, "registered");
    return merged ? void() : ctx_.Accept(id, t);
  }
  if (T_prev_curr_imu) {
    const SE3 deviation = T_prev_curr_imu->Inverse() * r.T_prev_curr;
    if (deviation.translation().norm() > options_.lidar.max_prior_deviation_m) {
      ctx_.Count(id, "deviates_from_imu_prior");
      return ctx_.Reject(id, t, RejectReason::kMahalanobisGate);
    }
  }
  Mat6 covariance = options_.lidar.covariance_scale * r.covariance;
  covariance.diagonal().head<3>().array() +=
      options_.lidar.min_sigma_translation_m * options_.lidar.min_sigma_translation_m;
  covariance.diagonal().tail<3>().array() +=
      options_.lidar.min_sigma_rotation_rad * options_.lidar.min_sigma_rotation_rad;
  RelativePoseMeasurement m;
  m.T_s1_s2 = r.T_prev_curr;
  m.T_imu_sensor = lidar.T_imu_sensor;
  try {
    m.sqrt_information = SqrtInformationOfCovariance(covariance, "lidar relative pose");
  } catch (const InputError&) {
    return ctx_.Reject(id, t, RejectReason::kInvalidCovariance);
  }
  if (ctx_.smoother.AddRelativePose(r.prev_stamp_ns, t, m, options_.lidar.kernel,
                                    MountCorrection()) == AddResult::kTooOld) {
    return ctx_.Reject(id, t, RejectReason::kTooOld);
  }
  ctx_.Count(id, "registered");
  if (!merged) ctx_.Accept(id, t);
}

}  // namespace statebench::est
