#include "estimator/state_initializer.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "core/so3.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est {
namespace {

constexpr TimeNs kHistoryNs = 60 * kNsPerSecond;  // IMU and fixes kept before init
constexpr TimeNs kMovingTiltHalfWindowNs = 250 * kNsPerMillisecond;
constexpr TimeNs kSpeedBaselineNs = kNsPerSecond;  // fixes this far apart give the speed
constexpr double kMaxStillGravityError = 0.5;      // | |f| - g | in a still period, m/s^2

// Mean and per-axis standard deviation of a 3-vector signal.
struct Moments {
  Vec3 mean = Vec3::Zero();
  Vec3 std = Vec3::Zero();
};

template <typename Get>
Moments ComputeMoments(std::span<const ImuSample> samples, Get get) {
  Moments m;
  for (const ImuSample& s : samples) m.mean += get(s);
  m.mean /= static_cast<double>(samples.size());
  for (const ImuSample& s : samples) m.std += (get(s) - m.mean).cwiseAbs2();
  m.std = (m.std / static_cast<double>(samples.size())).cwiseSqrt();
  return m;
}

}  // namespace

StateInitializer::StateInitializer(const InitializationOptions& options, const ImuNoise& noise,
                                   const Vec3& forward_imu)
    : options_(options), noise_(noise), forward_imu_(forward_imu.normalized()) {}

void StateInitializer::AddImu(const ImuSample& sample) {
  imu_.push_back(sample);
  const TimeNs oldest = sample.header.stamp_ns - kHistoryNs;
  if (imu_.front().header.stamp_ns < oldest - 10 * kNsPerSecond) {  // trim in chunks
    std::erase_if(imu_, [&](const ImuSample& s) { return s.header.stamp_ns < oldest; });
  }
  if (still_ && still_->t_ns < imu_.front().header.stamp_ns) still_.reset();  // too old to use
  UpdateStill();
}

void StateInitializer::AddPosition(const GnssPositionEnu& fix, const Vec3& p_imu_antenna) {
  fixes_.push_back({fix, p_imu_antenna});
  while (fixes_.front().fix.header.stamp_ns < fix.header.stamp_ns - kHistoryNs) fixes_.pop_front();
}

void StateInitializer::AddHeading(const DualAntennaHeading& heading, const Vec3& baseline_imu) {
  YawReference ref;
  ref.t_ns = heading.header.stamp_ns;
  ref.direction_imu = baseline_imu;
  ref.yaw_rad = heading.yaw_rad;
  ref.sigma_rad = heading.yaw_sigma_rad;
  ref.method = "dual antenna";
  heading_ = ref;
}

void StateInitializer::UpdateStill() {
  const TimeNs t_end = imu_.back().header.stamp_ns;
  const TimeNs t_begin = t_end - FromSeconds(options_.static_duration_s);
  if (imu_.front().header.stamp_ns > t_begin) return;  // not enough data yet
  const auto first =
      std::lower_bound(imu_.begin(), imu_.end(), t_begin,
                       [](const ImuSample& s, TimeNs t) { return s.header.stamp_ns < t; });
  const std::span<const ImuSample> window(first, imu_.end());
  if (window.size() < 2) return;
  const Moments gyro = ComputeMoments(window, [](const ImuSample& s) { return s.gyro; });
  const Moments accel = ComputeMoments(window, [](const ImuSample& s) { return s.accel; });
  if (gyro.std.maxCoeff() > options_.static_max_gyro_std_radps ||
      accel.std.maxCoeff() > options_.static_max_accel_std_mps2 ||
      std::abs(accel.mean.norm() - kGravity) > kMaxStillGravityError ||
      gyro.mean.norm() > 10.0 * options_.static_max_gyro_std_radps) {
    return;
  }
  // A constant velocity looks still to an IMU: the fixes of the period must not move.
  for (const Fix& a : fixes_) {
    if (a.fix.header.stamp_ns < t_begin) continue;
    const Vec3 d = a.fix.p_enu - fixes_.back().fix.p_enu;
    const double sigma = std::sqrt(a.fix.covariance(0, 0) + a.fix.covariance(1, 1));
    if (d.head<2>().norm() > 0.05 + 4.0 * sigma) return;
  }
  Tilt tilt;
  tilt.t_ns = t_end;
  tilt.up_imu = accel.mean.normalized();
  tilt.gyro_bias = gyro.mean;
  tilt.still = true;
  still_ = tilt;
}

double StateInitializer::SpeedEstimate() const {
  if (fixes_.size() < 2) return 0.0;
  const Fix& b = fixes_.back();
  for (auto it = fixes_.rbegin(); it != fixes_.rend(); ++it) {
    const TimeNs dt_ns = b.fix.header.stamp_ns - it->fix.header.stamp_ns;
    if (dt_ns >= kSpeedBaselineNs) {
      return (b.fix.p_enu - it->fix.p_enu).head<2>().norm() / ToSeconds(dt_ns);
    }
  }
  return 0.0;
}

const StateInitializer::Fix* StateInitializer::VelocityPartner(TimeNs t_min_ns) const {
  const Fix& b = fixes_.back();
  // Baseline long enough for a velocity error of about 0.2 m/s from the fix noise.
  const double sigma = std::sqrt(b.fix.covariance.trace());
  const TimeNs baseline_ns =
      std::clamp(FromSeconds(sigma / 0.2), kSpeedBaselineNs, 10 * kSpeedBaselineNs);
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
    ref.sigma_rad = std::max(options_.course_yaw_sigma_rad, std::sqrt(2.0) * sigma_h / length);
    ref.speed_mps = length / ToSeconds(b.fix.header.stamp_ns - it->fix.header.stamp_ns);
    ref.method = "gnss course";
    return ref;
  }
  return std::nullopt;
}

std::optional<StateInitializer::Tilt> StateInitializer::MovingTilt(TimeNs t_ns,
                                                                   double speed_mps) const {
  const TimeNs t_begin = t_ns - kMovingTiltHalfWindowNs;
  const TimeNs t_end = t_ns + kMovingTiltHalfWindowNs;
  if (imu_.front().header.stamp_ns > t_begin || imu_.back().header.stamp_ns < t_end) {
    return std::nullopt;
  }
  Vec3 f = Vec3::Zero(), w = Vec3::Zero();
  int n = 0;
  for (const ImuSample& s : imu_) {
    if (s.header.stamp_ns < t_begin || s.header.stamp_ns > t_end) continue;
    f += s.accel;
    w += s.gyro;
    ++n;
  }
  f /= n;
  w /= n;
  // f = a_imu - R^T g_world with a_imu ~ w x (s forward): up_imu = (f - a_imu) / |.|.
  Tilt tilt;
  tilt.t_ns = t_ns;
  tilt.up_imu = (f - w.cross(speed_mps * forward_imu_)).normalized();
  tilt.still = false;
  return tilt;
}

Quat StateInitializer::GyroDelta(TimeNs from_ns, TimeNs to_ns, const Vec3& gyro_bias) const {
  if (to_ns <= from_ns) return Quat::Identity();
  return ImuPreintegration::FromSamples(std::span<const ImuSample>(imu_), from_ns, to_ns, noise_,
                                        ImuBias{gyro_bias, Vec3::Zero()})
      .delta_q();
}

std::optional<InitialState> StateInitializer::TryInitialize() {
  if (imu_.empty() || fixes_.empty()) return std::nullopt;
  const InitializationMode mode = options_.mode;
  const bool use_still = still_.has_value() && mode != InitializationMode::kMoving;
  if (mode == InitializationMode::kStatic && !use_still) return std::nullopt;

  std::optional<YawReference> yaw = heading_;
  if (!yaw) yaw = CourseReference();
  if (!yaw) return std::nullopt;
  const TimeNs t0 = imu_.back().header.stamp_ns;
  const TimeNs t_imu_begin = imu_.front().header.stamp_ns;
  if (yaw->t_ns < t_imu_begin) return std::nullopt;
  const bool still_now = use_still && still_->t_ns == t0;
  const double speed = still_now ? 0.0 : (yaw->speed_mps > 0.0 ? yaw->speed_mps : SpeedEstimate());

  std::optional<Tilt> tilt = use_still ? still_ : MovingTilt(yaw->t_ns, speed);
  if (!tilt) return std::nullopt;

  // Attitude with the right tilt and an arbitrary yaw, carried to t0 by the gyro; then the yaw
  // rotation about world z that aligns the reference direction at its stamp.
  const Quat q_tilt = Quat::FromTwoVectors(tilt->up_imu, Vec3::UnitZ());
  const Quat q_a_t0 = (q_tilt * GyroDelta(tilt->t_ns, t0, tilt->gyro_bias)).normalized();
  const Quat q_a_ref = q_a_t0 * GyroDelta(yaw->t_ns, t0, tilt->gyro_bias).conjugate();
  const Vec3 d_world = q_a_ref * yaw->direction_imu;
  const double delta = so3::WrapAngle(yaw->yaw_rad - std::atan2(d_world.y(), d_world.x()));
  const Quat q0 = (Eigen::AngleAxisd(delta, Vec3::UnitZ()) * q_a_t0).normalized();

  // Position and velocity: the newest fix b moved to the IMU; the velocity from b and an earlier
  // fix a through the IMU displacement between them (p_b = p_a + v_a dt + g dt^2 / 2 + R_a dp),
  // then b is carried to t0 with the IMU.
  const Fix& b = fixes_.back();
  const TimeNs t_b = b.fix.header.stamp_ns;
  if (t_b < t_imu_begin || t_b > t0) return std::nullopt;
  const Vec3& bg = tilt->gyro_bias;
  const auto q_at = [&](TimeNs t) { return Quat(q0 * GyroDelta(t, t0, bg).conjugate()); };
  const auto preintegrate = [&](TimeNs from, TimeNs to) {
    return ImuPreintegration::FromSamples(std::span<const ImuSample>(imu_), from, to, noise_,
                                          ImuBias{bg, Vec3::Zero()});
  };
  NavState at_b;
  at_b.t_ns = t_b;
  at_b.q_world_imu = q_at(t_b);
  at_b.p_world = b.fix.p_enu - at_b.q_world_imu * b.p_imu_antenna;
  at_b.gyro_bias = bg;
  double sigma_v_fix = 0.0;
  if (!still_now) {
    const Fix* a = VelocityPartner(t_imu_begin);
    if (a == nullptr) return std::nullopt;
    const TimeNs t_a = a->fix.header.stamp_ns;
    const double dt = ToSeconds(t_b - t_a);
    const ImuPreintegration pim = preintegrate(t_a, t_b);
    const Quat q_a = q_at(t_a);
    const Vec3 p_a = a->fix.p_enu - q_a * a->p_imu_antenna;
    const Vec3 v_a =
        (at_b.p_world - p_a - 0.5 * kGravityWorld * dt * dt - q_a * pim.delta_p()) / dt;
    at_b.v_world = v_a + kGravityWorld * dt + q_a * pim.delta_v();
    sigma_v_fix = std::sqrt(a->fix.covariance.trace() + b.fix.covariance.trace()) / dt;
  }
  const NavState s0 = t0 > t_b ? preintegrate(t_b, t0).Predict(at_b) : at_b;

  InitialState out;
  out.state = s0;
  out.state.t_ns = t0;
  out.state.q_world_imu = q0;

  const InitializationOptions& o = options_;
  const double sigma_tilt = tilt->still ? o.roll_pitch_sigma_rad : o.moving_roll_pitch_sigma_rad;
  const double sigma_v = still_now ? o.static_velocity_sigma_mps
                                   : std::hypot(o.moving_velocity_sigma_mps, sigma_v_fix);
  const double sigma_bg =
      tilt->still ? std::max(2.0 * noise_.gyro_noise_density / std::sqrt(o.static_duration_s), 1e-4)
                  : o.gyro_bias_sigma_radps;
  const Mat3 R0 = q0.toRotationMatrix();
  const Vec3 world_rotation_var(sigma_tilt * sigma_tilt, sigma_tilt * sigma_tilt,
                                yaw->sigma_rad * yaw->sigma_rad);
  const double attitude_sigma = std::max(sigma_tilt, yaw->sigma_rad);
  const double lever = b.p_imu_antenna.norm() * attitude_sigma;
  const double drift = sigma_v * ToSeconds(t0 - t_b);
  Mat15& P = out.covariance;
  P.setZero();
  P.block<3, 3>(kRotationIndex, kRotationIndex) =
      R0.transpose() * world_rotation_var.asDiagonal() * R0;
  P.block<3, 3>(kPositionIndex, kPositionIndex) =
      b.fix.covariance + (lever * lever + drift * drift) * Mat3::Identity();
  P.block<3, 3>(kVelocityIndex, kVelocityIndex) = sigma_v * sigma_v * Mat3::Identity();
  P.block<3, 3>(kGyroBiasIndex, kGyroBiasIndex) = sigma_bg * sigma_bg * Mat3::Identity();
  P.block<3, 3>(kAccelBiasIndex, kAccelBiasIndex) =
      o.accel_bias_sigma_mps2 * o.accel_bias_sigma_mps2 * Mat3::Identity();
  out.method = std::string(tilt->still ? "static" : "moving") + " (" + yaw->method + ")";
  return out;
}

}  // namespace statebench::est
