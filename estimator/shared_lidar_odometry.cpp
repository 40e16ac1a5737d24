#include "estimator/shared_lidar_odometry.hpp"

#include <algorithm>
#include <cstdio>

#include "core/error.hpp"

namespace statebench::est {
namespace {

void Put(std::string* key, double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g,", v);
  *key += buffer;
}

LidarOdometryResult NotRegistered(const LidarScan& scan, const std::string& why) {
  LidarOdometryResult r;
  r.stamp_ns = scan.header.stamp_ns;
  r.reject_reason = why;
  return r;
}

}  // namespace

std::string SharedOdometryKey(const LidarSetKey& lidars, const std::optional<Quat>& q_imu_lidar,
                              const LidarOdometryOptions& o) {
  std::string key = "intake:" + lidars.intake + ";gyro:";
  if (q_imu_lidar) {
    for (const double c : {q_imu_lidar->w(), q_imu_lidar->x(), q_imu_lidar->y(), q_imu_lidar->z()}) {
      Put(&key, c);
    }
  }
  key += ";";
  for (const auto& [id, T] : lidars.mounts) {
    key += id + ":";
    for (int k = 0; k < 3; ++k) Put(&key, T.translation()[k]);
    const Quat& q = T.rotation();
    for (const double c : {q.w(), q.x(), q.y(), q.z()}) Put(&key, c);
    key += ";";
  }
  for (const double v : {o.min_range_m, o.max_range_m, o.voxel_size_m,
                         static_cast<double>(o.max_points_per_voxel), o.map_downsample_factor,
                         o.register_downsample_factor, o.initial_threshold_m, o.min_motion_m,
                         static_cast<double>(o.min_points)}) {
    Put(&key, v);
  }
  const IcpOptions& i = o.icp;
  for (const double v :
       {static_cast<double>(i.metric), static_cast<double>(i.max_iterations), i.convergence_dx,
        static_cast<double>(i.min_correspondences), i.surface_radius_m, i.wide_surface_radius_m,
        i.thin_ratio, i.degeneracy_length_m, i.min_information, i.degenerate_variance,
        i.min_residual_sigma_m}) {
    Put(&key, v);
  }
  return key;
}

// Rotation from the raw gyro (in the lidar frame), translation from the odometry's constant
// velocity; nullopt (the odometry's own model) until it has a velocity or when the gyro does not
// cover the motion.
std::optional<LidarMotionPrior> SharedLidarOdometry::GyroPrior(TimeNs t, TimeNs sweep_end_ns,
                                                               const GyroTrack& gyro) const {
  const std::optional<Vec6> twist = odometry_.twist();
  const std::optional<TimeNs> prev = odometry_.last_stamp_ns();
  if (!twist || !prev || *prev >= t) return std::nullopt;
  const Quat& q_il = *q_imu_lidar_;
  const auto lidar_rotation = [&](TimeNs t0, TimeNs t1) -> std::optional<Quat> {
    const std::optional<Quat> q = gyro.Rotation(t0, t1);
    if (!q) return std::nullopt;
    return q_il.conjugate() * *q * q_il;
  };
  const auto translation = [&](double dt_s) { return SE3::Exp(*twist * dt_s).translation(); };
  const std::optional<Quat> q_prev_curr = lidar_rotation(*prev, t);
  if (!q_prev_curr) return std::nullopt;
  constexpr TimeNs kStep = 5 * kNsPerMillisecond;
  std::vector<std::pair<double, SE3>> table;
  for (TimeNs tk = t;; tk = std::min(sweep_end_ns, tk + kStep)) {
    const std::optional<Quat> q = lidar_rotation(t, tk);
    if (!q) return std::nullopt;
    const double ts = ToSeconds(tk - t);
    table.emplace_back(ts, SE3(*q, translation(ts)));
    if (tk >= sweep_end_ns) break;
  }
  LidarMotionPrior p;
  p.T_prev_curr = SE3(*q_prev_curr, translation(ToSeconds(t - *prev)));
  p.sweep = TabulatedSweepMotion(std::move(table));
  return p;
}

LidarOdometryResult SharedLidarOdometry::Register(const LidarScan& scan, TimeNs sweep_end_ns,
                                                  const GyroTrack* gyro, bool* computed) {
  if (computed != nullptr) *computed = false;
  const TimeNs t = scan.header.stamp_ns;
  const std::size_t points = scan.points ? scan.points->size() : 0;
  const auto it = std::lower_bound(recent_.begin(), recent_.end(), t,
                                   [](const Entry& e, TimeNs s) { return e.stamp_ns < s; });
  if (it != recent_.end() && it->stamp_ns == t) {
    if (it->points != points) {
      return NotRegistered(scan, "not registered (another scan of this stamp was registered "
                                 "by the shared odometry)");
    }
    ++reused_;
    return it->result;
  }
  if (it != recent_.end()) {
    return NotRegistered(scan, "not registered (the shared odometry is past this scan)");
  }
  Entry e{t, points, Compute(scan, points, sweep_end_ns, gyro)};
  ++registered_;
  if (computed != nullptr) *computed = true;
  if (keep_all_) all_.push_back({t, points, e.result});
  recent_.push_back(std::move(e));
  if (recent_.size() > kRecentScans) recent_.pop_front();
  return recent_.back().result;
}

void SharedLidarOdometry::Replay(std::vector<RecordedRegistration> recorded) {
  replay_ = std::move(recorded);
  replay_next_ = 0;
}

LidarOdometryResult SharedLidarOdometry::Compute(const LidarScan& scan, std::size_t points,
                                                 TimeNs sweep_end_ns, const GyroTrack* gyro) {
  if (replay_) {
    if (replay_next_ >= replay_->size() ||
        (*replay_)[replay_next_].stamp_ns != scan.header.stamp_ns ||
        (*replay_)[replay_next_].points != points) {
      throw InputError("the recorded lidar registrations do not match the scans (scan at " +
                       std::to_string(ToSeconds(scan.header.stamp_ns)) + " s)");
    }
    return (*replay_)[replay_next_++].result;
  }
  std::optional<LidarMotionPrior> prior;
  if (q_imu_lidar_ && gyro != nullptr) prior = GyroPrior(scan.header.stamp_ns, sweep_end_ns, *gyro);
  return odometry_.RegisterScan(scan, prior);
}

void LidarOdometryPool::Finish() {
  if (store_ == nullptr) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [key, odometry] : odometries_) {
    if (!odometry->replaying()) store_->Save(key, odometry->all());
  }
}

std::shared_ptr<SharedLidarOdometry> LidarOdometryPool::For(const LidarSetKey& lidars,
                                                            const std::optional<Quat>& q_imu_lidar,
                                                            const LidarOdometryOptions& options) {
  const std::string key = SharedOdometryKey(lidars, q_imu_lidar, options);
  const std::lock_guard<std::mutex> lock(mutex_);
  std::shared_ptr<SharedLidarOdometry>& o = odometries_[key];
  if (!o) {
    o = std::make_shared<SharedLidarOdometry>(options, q_imu_lidar);
    if (store_ != nullptr) {
      if (auto recorded = store_->Load(key)) {
        o->Replay(std::move(*recorded));
      } else {
        o->KeepAll();
      }
    }
  }
  return o;
}

std::vector<std::pair<std::size_t, std::size_t>> LidarOdometryPool::Counts() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::pair<std::size_t, std::size_t>> counts;
  for (const auto& [key, odometry] : odometries_) {
    counts.emplace_back(odometry->registered(), odometry->reused());
  }
  return counts;
}

std::size_t LidarOdometryPool::size() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return odometries_.size();
}

}  // namespace statebench::est
