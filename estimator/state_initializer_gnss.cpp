#include "estimator/state_initializer.hpp"

// What the GNSS fixes tell the initialiser (state_initializer.hpp): standstill proofs from
// positions and Doppler velocities, and course references from a chord or a velocity.
#include <algorithm>
#include <cmath>

#include "estimator/body_velocity_front_end.hpp"

namespace statebench::est {

bool StateInitializer::FixesProveStandstill(TimeNs from_ns, TimeNs to_ns) const {
  // Horizontal velocity fitted to the fixes (p = p0 + v t), with its standard deviation from
  // the fixes' mean horizontal variance per axis.
  double t_mean = 0.0;
  Vec2 p_mean = Vec2::Zero();
  double variance = 0.0;
  int n = 0;
  for (const Fix& f : fixes_) {
    const TimeNs t = f.fix.header.stamp_ns;
    if (t < from_ns || t > to_ns) continue;
    t_mean += ToSeconds(t - from_ns);
    p_mean += f.fix.p_enu.head<2>();
    variance += 0.5 * (f.fix.covariance(0, 0) + f.fix.covariance(1, 1));
    ++n;
  }
  if (n < 3) return false;
  t_mean /= n;
  p_mean /= n;
  variance /= n;
  double spread = 0.0;
  Vec2 moment = Vec2::Zero();
  for (const Fix& f : fixes_) {
    const TimeNs t = f.fix.header.stamp_ns;
    if (t < from_ns || t > to_ns) continue;
    const double dt = ToSeconds(t - from_ns) - t_mean;
    spread += dt * dt;
    moment += dt * (f.fix.p_enu.head<2>() - p_mean);
  }
  if (!(spread > 0.0)) return false;
  const Vec2 v = moment / spread;
  const double sigma_v = std::sqrt(variance / spread);
  return v.norm() + 3.0 * sigma_v <= options_.static_max_speed_mps;
}

bool StateInitializer::OdometryProvesStandstill(TimeNs from_ns, TimeNs to_ns) const {
  if (!local_.has_odometry) return true;
  Vec3 sum = Vec3::Zero(), variance_sum = Vec3::Zero();
  Eigen::Vector3i count = Eigen::Vector3i::Zero();
  for (const OdometryVelocity& v : odometry_) {
    if (v.t_ns < from_ns || v.t_ns > to_ns) continue;
    for (int i = 0; i < 3; ++i) {
      if (!(v.variance[i] < BodyVelocityFrontEnd::kUnmeasuredVariance)) continue;
      sum[i] += v.v_frame[i];
      variance_sum[i] += v.variance[i];
      ++count[i];
    }
  }
  if (count.maxCoeff() < 2) return false;
  for (int i = 0; i < 3; ++i) {
    if (count[i] == 0) continue;
    const double mean = sum[i] / count[i];
    if (std::abs(mean) + 3.0 * std::sqrt(variance_sum[i]) / count[i] >
        options_.static_max_speed_mps) {
      return false;
    }
  }
  return true;
}

const StateInitializer::Fix* StateInitializer::EarlierFix(TimeNs min_baseline_ns,
                                                          TimeNs t_min_ns) const {
  const Fix& b = fixes_.back();
  // Long enough for a velocity error of about 0.2 m/s from the fix noise.
  const double sigma = std::sqrt(b.fix.covariance.trace());
  const TimeNs baseline_ns =
      std::clamp(FromSeconds(sigma / 0.2), min_baseline_ns, 10 * kNsPerSecond);
  for (auto it = fixes_.rbegin(); it != fixes_.rend(); ++it) {
    const TimeNs t = it->fix.header.stamp_ns;
    if (t < t_min_ns) break;
    if (b.fix.header.stamp_ns - t >= baseline_ns) return &*it;
  }
  return nullptr;
}

std::optional<StateInitializer::YawReference> StateInitializer::CourseReference() const {
  if (fixes_.size() < 2) return std::nullopt;
  const Fix& b = fixes_.back();
  for (auto it = std::next(fixes_.rbegin()); it != fixes_.rend(); ++it) {
    const Vec3 chord = b.fix.p_enu - it->fix.p_enu;
    const double sigma_h = std::sqrt(0.5 * (b.fix.covariance(0, 0) + b.fix.covariance(1, 1) +
                                            it->fix.covariance(0, 0) + it->fix.covariance(1, 1)));
    // Noisy fixes need a longer chord: the yaw error is about sqrt(2) sigma_h / length.
    const double min_length = std::max(options_.course_min_distance_m, 15.0 * sigma_h);
    const double length = chord.head<2>().norm();
    if (length < min_length) continue;
    YawReference ref;
    ref.t_ns = (b.fix.header.stamp_ns + it->fix.header.stamp_ns) / 2;
    ref.direction_imu = forward_imu_;
    ref.yaw_rad = std::atan2(chord.y(), chord.x());
    ref.pitch_rad = std::atan2(-chord.z(), length);
    ref.sigma_rad = std::max(options_.course_yaw_sigma_rad, std::sqrt(2.0) * sigma_h / length);
    ref.method = "gnss course";
    return ref;
  }
  return std::nullopt;
}

std::optional<bool> StateInitializer::VelocitiesProveStandstill(TimeNs from_ns,
                                                                TimeNs to_ns) const {
  Vec2 sum = Vec2::Zero();
  double variance_sum = 0.0;  // of one horizontal axis
  int n = 0;
  for (const Fix& f : fixes_) {
    const TimeNs t = f.fix.header.stamp_ns;
    if (t < from_ns || t > to_ns || !f.fix.velocity) continue;
    const GnssVelocity& v = *f.fix.velocity;
    sum += v.v_enu.head<2>();
    variance_sum += 0.5 * v.sigma_enu.head<2>().squaredNorm();
    ++n;
  }
  if (n < 2) return std::nullopt;
  const double sigma_mean = std::sqrt(variance_sum) / n;
  return (sum / n).norm() + 3.0 * sigma_mean <= options_.static_max_speed_mps;
}

Vec3 StateInitializer::GyroNear(TimeNs t_ns) const {
  auto it = std::lower_bound(imu_.begin(), imu_.end(), t_ns,
                             [](const ImuSample& s, TimeNs t) { return s.header.stamp_ns < t; });
  if (it == imu_.end()) return imu_.back().gyro;
  if (it != imu_.begin() && t_ns - std::prev(it)->header.stamp_ns < it->header.stamp_ns - t_ns) {
    --it;
  }
  return it->gyro;
}

Vec3 StateInitializer::ImuVelocityFromFix(const Fix& f, const Quat& q_world_imu,
                                          const Vec3& gyro_bias) const {
  const Vec3 omega = GyroNear(f.fix.header.stamp_ns) - gyro_bias;
  return f.fix.velocity->v_enu - q_world_imu * omega.cross(f.p_imu_antenna);
}

std::optional<StateInitializer::YawReference> StateInitializer::VelocityCourseReference() const {
  if (fixes_.empty() || imu_.empty() || !fixes_.back().fix.velocity) return std::nullopt;
  const Fix& f = fixes_.back();
  const GnssVelocity& v = *f.fix.velocity;
  const double speed = v.v_enu.head<2>().norm();
  const double sigma_h = v.sigma_enu.head<2>().maxCoeff();
  if (speed < std::max(options_.velocity_course_min_speed_mps, 10.0 * sigma_h)) {
    return std::nullopt;
  }
  // The antenna moves at s f + u in the IMU frame (u = w x l, the gyro bias neglected): s >= 0
  // from |s f + u| = |v|.
  const Vec3 u = GyroNear(f.fix.header.stamp_ns).cross(f.p_imu_antenna);
  const double fu = forward_imu_.dot(u);
  const double discriminant = fu * fu - u.squaredNorm() + v.v_enu.squaredNorm();
  if (discriminant < 0.0) return std::nullopt;
  YawReference ref;
  ref.t_ns = f.fix.header.stamp_ns;
  ref.direction_imu = (-fu + std::sqrt(discriminant)) * forward_imu_ + u;
  ref.yaw_rad = std::atan2(v.v_enu.y(), v.v_enu.x());
  ref.pitch_rad = std::atan2(-v.v_enu.z(), speed);
  ref.sigma_rad = std::max(options_.course_yaw_sigma_rad, sigma_h / speed);
  ref.method = "gnss velocity";
  return ref;
}

}  // namespace statebench::est
