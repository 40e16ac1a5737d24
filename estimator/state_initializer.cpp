#include "estimator/state_initializer.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include "core/so3.hpp"
#include "estimator/imu_preintegration.hpp"
#include "estimator/imu_window_statistics.hpp"

namespace statebench::est {
namespace {

constexpr TimeNs kHistoryNs = 60 * kNsPerSecond;  // IMU and fixes kept before init

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

// Rotation R with R b1 parallel to r1 and R b2 as close to r2 as the first allows (TRIAD).
Quat Triad(const Vec3& b1, const Vec3& r1, const Vec3& b2, const Vec3& r2) {
  const auto frame = [](const Vec3& v1, const Vec3& v2) {
    Mat3 m;
    m.col(0) = v1.normalized();
    m.col(1) = v1.cross(v2).normalized();
    m.col(2) = m.col(0).cross(m.col(1));
    return m;
  };
  return Quat(frame(r1, r2) * frame(b1, b2).transpose()).normalized();
}

}  // namespace

StateInitializer::StateInitializer(const InitializationOptions& options, const ImuNoise& noise,
                                   const Vec3& forward_imu, LocalStart local)
    : options_(options), noise_(noise), forward_imu_(forward_imu.normalized()), local_(local) {}

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

void StateInitializer::AddVelocity(const OdometryVelocity& velocity) {
  if (!local_.enabled) return;
  odometry_.push_back(velocity);
  odometry_since_fit_ = true;
  while (odometry_.front().t_ns < velocity.t_ns - kHistoryNs) odometry_.pop_front();
}

void StateInitializer::AddHeading(const DualAntennaHeading& heading, const Vec3& baseline_imu) {
  YawReference ref;
  ref.t_ns = heading.header.stamp_ns;
  ref.direction_imu = baseline_imu;
  ref.yaw_rad = heading.yaw_rad;
  ref.pitch_rad = heading.pitch_sigma_rad > 0.0 ? heading.pitch_rad : 0.0;
  ref.sigma_rad = heading.yaw_sigma_rad;
  ref.method = "dual antenna";
  heading_ = ref;
}

void StateInitializer::UpdateStill() {
  TimeNs t_end = imu_.back().header.stamp_ns;
  const TimeNs t_begin = t_end - FromSeconds(options_.static_duration_s);
  if (imu_.front().header.stamp_ns > t_begin) return;  // not enough data yet
  const auto first =
      std::lower_bound(imu_.begin(), imu_.end(), t_begin,
                       [](const ImuSample& s, TimeNs t) { return s.header.stamp_ns < t; });
  std::span<const ImuSample> window(first, imu_.end());
  if (window.size() < 2) return;
  Moments gyro = ComputeMoments(window, [](const ImuSample& s) { return s.gyro; });
  Moments accel = ComputeMoments(window, [](const ImuSample& s) { return s.accel; });
  // An engine running: the window is still when its low band is quiet to half the thresholds
  // (the stds tested and reported are then the low band's over that share; else the raw ones).
  if (options_.static_lowpass_s > 0.0 &&
      (gyro.std.maxCoeff() > options_.static_max_gyro_std_radps ||
       accel.std.maxCoeff() > options_.static_max_accel_std_mps2)) {
    const ImuBands bands = SplitImuBands(window, options_.static_lowpass_s);
    const Vec3 low_gyro = bands.gyro.lowpass_std / kLowBandThresholdShare;
    const Vec3 low_accel = bands.accel.lowpass_std / kLowBandThresholdShare;
    if (bands.valid() && !(low_gyro.maxCoeff() > options_.static_max_gyro_std_radps) &&
        !(low_accel.maxCoeff() > options_.static_max_accel_std_mps2)) {
      // The low band sees the window's newest (and oldest) taps - 1 samples only faintly: a
      // start of motion there would pass it. The still period is the samples it centres on, and
      // its means theirs.
      const std::size_t edge = static_cast<std::size_t>(bands.taps - 1);
      window = window.subspan(edge, window.size() - 2 * edge);
      t_end = window.back().header.stamp_ns;
      gyro.mean = ComputeMoments(window, [](const ImuSample& s) { return s.gyro; }).mean;
      accel.mean = ComputeMoments(window, [](const ImuSample& s) { return s.accel; }).mean;
      gyro.std = low_gyro;
      accel.std = low_accel;
    }
  }
  const double gravity_error = std::abs(accel.mean.norm() - kGravity);
  const double score = std::max({gyro.std.maxCoeff() / options_.static_max_gyro_std_radps,
                                 accel.std.maxCoeff() / options_.static_max_accel_std_mps2,
                                 gravity_error / kMaxStillGravityError,
                                 gyro.mean.norm() / (10.0 * options_.static_max_gyro_std_radps)});
  if (!still_record_.tested || score < still_record_.score) {
    still_record_.score = score;
    still_record_.gyro_std = gyro.std.maxCoeff();
    still_record_.accel_std = accel.std.maxCoeff();
    still_record_.gravity_error = gravity_error;
    still_record_.mean_rate = gyro.mean.norm();
  }
  still_record_.tested = true;
  if (gyro.std.maxCoeff() > options_.static_max_gyro_std_radps ||
      accel.std.maxCoeff() > options_.static_max_accel_std_mps2 ||
      gravity_error > kMaxStillGravityError ||
      gyro.mean.norm() > 10.0 * options_.static_max_gyro_std_radps) {
    still_since_ns_.reset();
    return;
  }
  if (!still_since_ns_) still_since_ns_ = t_begin;
  if (local_.enabled) {
    if (!OdometryProvesStandstill(t_begin, t_end)) {
      still_record_.not_proven = NotProven::kOdometryMoving;
      return;
    }
  } else {
    // A constant velocity looks still to an IMU: the fixes of the period must not move.
    for (const Fix& a : fixes_) {
      if (a.fix.header.stamp_ns < t_begin) continue;
      const Vec3 d = a.fix.p_enu - fixes_.back().fix.p_enu;
      const double sigma = std::sqrt(a.fix.covariance(0, 0) + a.fix.covariance(1, 1));
      if (d.head<2>().norm() > 0.05 + 4.0 * sigma) {
        still_record_.not_proven = NotProven::kFixesMoved;
        return;
      }
    }
    const std::optional<bool> by_velocity = VelocitiesProveStandstill(*still_since_ns_, t_end);
    if (!(by_velocity ? *by_velocity : FixesProveStandstill(*still_since_ns_, t_end))) {
      still_record_.not_proven = NotProven::kFixesNoProof;
      return;
    }
  }
  Tilt tilt;
  tilt.t_ns = t_end;
  tilt.up_imu = accel.mean.normalized();
  tilt.gyro_bias = gyro.mean;
  still_ = tilt;
}

ImuPreintegration StateInitializer::Preintegrate(TimeNs from_ns, TimeNs to_ns,
                                                 const Vec3& gyro_bias) const {
  return ImuPreintegration::FromSamples(std::span<const ImuSample>(imu_), from_ns, to_ns, noise_,
                                        ImuBias{gyro_bias, Vec3::Zero()});
}

Quat StateInitializer::GyroDelta(TimeNs from_ns, TimeNs to_ns, const Vec3& gyro_bias) const {
  if (from_ns == to_ns) return Quat::Identity();
  if (to_ns < from_ns) return GyroDelta(to_ns, from_ns, gyro_bias).conjugate();
  return Preintegrate(from_ns, to_ns, gyro_bias).delta_q();
}

std::optional<StateInitializer::Anchor> StateInitializer::StaticAnchor(const YawReference& yaw,
                                                                       TimeNs t0_ns) const {
  const Tilt& tilt = *still_;
  const Vec3& bg = tilt.gyro_bias;
  // Attitude with the right tilt and an arbitrary yaw, carried to t0 by the gyro; then the yaw
  // rotation about world z that aligns the reference direction at its stamp.
  const Quat q_tilt = Quat::FromTwoVectors(tilt.up_imu, Vec3::UnitZ());
  const Quat q_a_t0 = (q_tilt * GyroDelta(tilt.t_ns, t0_ns, bg)).normalized();
  const Vec3 d_world = q_a_t0 * GyroDelta(t0_ns, yaw.t_ns, bg) * yaw.direction_imu;
  const double delta = so3::WrapAngle(yaw.yaw_rad - std::atan2(d_world.y(), d_world.x()));
  const Quat q0 = (Eigen::AngleAxisd(delta, Vec3::UnitZ()) * q_a_t0).normalized();

  // The newest fix b moved to the IMU; the velocity from b and an earlier fix a through the IMU
  // displacement between them: p_b = p_a + v_a dt + g dt^2 / 2 + R_a dp.
  const Fix& b = fixes_.back();
  Anchor anchor;
  anchor.still_now = still_->t_ns == t0_ns;
  anchor.sigma_tilt = options_.roll_pitch_sigma_rad;
  NavState& x = anchor.state;
  x.t_ns = b.fix.header.stamp_ns;
  x.q_world_imu = q0 * GyroDelta(t0_ns, x.t_ns, bg);
  x.p_world = b.fix.p_enu - x.q_world_imu * b.p_imu_antenna;
  x.gyro_bias = bg;
  if (anchor.still_now) return anchor;
  if (b.fix.velocity) {
    x.v_world = ImuVelocityFromFix(b, x.q_world_imu, bg);
    anchor.sigma_v_fix = b.fix.velocity->sigma_enu.norm();
    return anchor;
  }
  const Fix* a = EarlierFix(kNsPerSecond, imu_.front().header.stamp_ns);
  if (a == nullptr) return std::nullopt;
  const TimeNs t_a = a->fix.header.stamp_ns;
  const double dt = ToSeconds(x.t_ns - t_a);
  const ImuPreintegration pim = Preintegrate(t_a, x.t_ns, bg);
  const Quat q_a = q0 * GyroDelta(t0_ns, t_a, bg);
  const Vec3 p_a = a->fix.p_enu - q_a * a->p_imu_antenna;
  const Vec3 v_a = (x.p_world - p_a - 0.5 * kGravityWorld * dt * dt - q_a * pim.delta_p()) / dt;
  x.v_world = v_a + kGravityWorld * dt + q_a * pim.delta_v();
  anchor.sigma_v_fix = std::sqrt(a->fix.covariance.trace() + b.fix.covariance.trace()) / dt;
  return anchor;
}

std::optional<StateInitializer::Anchor> StateInitializer::MovingAnchor(
    const YawReference& yaw) const {
  // Three fixes a, m, b of one antenna path: with w_k = dp_k + dR_k l_k - l_a (preintegrated
  // from t_a, IMU frame at a) and tau_k = t_k - t_a,
  //   (p_k - p_a - g tau_k^2 / 2) / tau_k = v_a + R_a w_k / tau_k,
  // and the difference of k = b and k = m eliminates v_a: R_a (w_b / tau_b - w_m / tau_m) = L,
  // an exact vector observation of R_a (mostly gravity, plus whatever the vehicle accelerated).
  // TRIAD with the yaw reference as second vector gives R_a; then v_a from k = b.
  const Fix& b = fixes_.back();
  const Fix* a = EarlierFix(2 * kNsPerSecond, imu_.front().header.stamp_ns);
  if (a == nullptr) return std::nullopt;
  const TimeNs t_a = a->fix.header.stamp_ns;
  const TimeNs t_b = b.fix.header.stamp_ns;
  const Fix* m = nullptr;
  for (const Fix& f : fixes_) {
    const TimeNs t = f.fix.header.stamp_ns;
    if (t > t_a && t < t_b &&
        (m == nullptr ||
         std::abs(t - (t_a + t_b) / 2) < std::abs(m->fix.header.stamp_ns - (t_a + t_b) / 2))) {
      m = &f;
    }
  }
  if (m == nullptr) return std::nullopt;
  const Vec3 bg = Vec3::Zero();  // unknown while moving
  const auto observe = [&](const Fix& k, Vec3* world, Vec3* body) {
    const double tau = ToSeconds(k.fix.header.stamp_ns - t_a);
    const ImuPreintegration pim = Preintegrate(t_a, k.fix.header.stamp_ns, bg);
    *body = (pim.delta_p() + pim.delta_q() * k.p_imu_antenna - a->p_imu_antenna) / tau;
    *world = (k.fix.p_enu - a->fix.p_enu - 0.5 * kGravityWorld * tau * tau) / tau;
  };
  Vec3 world_b, body_b, world_m, body_m;
  observe(b, &world_b, &body_b);
  observe(*m, &world_m, &body_m);
  const Vec3 d_body = GyroDelta(t_a, yaw.t_ns, bg) * yaw.direction_imu;
  const Vec3 d_world(std::cos(yaw.pitch_rad) * std::cos(yaw.yaw_rad),
                     std::cos(yaw.pitch_rad) * std::sin(yaw.yaw_rad), -std::sin(yaw.pitch_rad));
  const Quat q_a = Triad(body_b - body_m, world_b - world_m, d_body, d_world);

  Anchor anchor;
  anchor.sigma_tilt = options_.moving_roll_pitch_sigma_rad;
  NavState& x = anchor.state;
  x.t_ns = t_a;
  x.q_world_imu = q_a;
  x.p_world = a->fix.p_enu - q_a * a->p_imu_antenna;
  x.v_world = world_b - q_a * body_b;
  anchor.sigma_v_fix =
      std::sqrt(a->fix.covariance.trace() + b.fix.covariance.trace()) / ToSeconds(t_b - t_a);
  FitMovingAnchor(*a, yaw, &anchor);
  return anchor;
}

std::optional<StateInitializer::Anchor> StateInitializer::VelocityAnchor(
    const YawReference& yaw) const {
  // Two fixes a, b with velocities: with u_k = w_k x l (IMU frame) and dv, dR preintegrated
  // from t_a, v_antenna_k = v_k + R_k u_k and v_b = v_a + g tau + R_a dv give
  //   R_a (dv + dR u_b - u_a) = v_antenna_b - v_antenna_a - g tau,
  // a vector observation of R_a (mostly gravity); TRIAD with the yaw reference gives R_a.
  const Fix& b = fixes_.back();
  if (!b.fix.velocity) return std::nullopt;
  const TimeNs t_b = b.fix.header.stamp_ns;
  const Fix* a = nullptr;
  for (auto it = fixes_.rbegin(); it != fixes_.rend(); ++it) {
    const TimeNs t = it->fix.header.stamp_ns;
    if (t < imu_.front().header.stamp_ns) break;
    if (t_b - t >= kNsPerSecond && it->fix.velocity) {
      a = &*it;
      break;
    }
  }
  if (a == nullptr) return std::nullopt;
  const TimeNs t_a = a->fix.header.stamp_ns;
  const double tau = ToSeconds(t_b - t_a);
  const Vec3 bg = Vec3::Zero();  // unknown while moving
  const ImuPreintegration pim = Preintegrate(t_a, t_b, bg);
  const Vec3 u_a = GyroNear(t_a).cross(a->p_imu_antenna);
  const Vec3 u_b = GyroNear(t_b).cross(b.p_imu_antenna);
  const Vec3 body = pim.delta_v() + pim.delta_q() * u_b - u_a;
  const Vec3 world = b.fix.velocity->v_enu - a->fix.velocity->v_enu - kGravityWorld * tau;
  const Vec3 d_body = GyroDelta(t_a, yaw.t_ns, bg) * yaw.direction_imu;
  const Vec3 d_world(std::cos(yaw.pitch_rad) * std::cos(yaw.yaw_rad),
                     std::cos(yaw.pitch_rad) * std::sin(yaw.yaw_rad), -std::sin(yaw.pitch_rad));
  Anchor anchor;
  anchor.sigma_tilt = options_.moving_roll_pitch_sigma_rad;
  NavState& x = anchor.state;
  x.t_ns = t_a;
  x.q_world_imu = Triad(body, world, d_body, d_world);
  x.p_world = a->fix.p_enu - x.q_world_imu * a->p_imu_antenna;
  x.v_world = ImuVelocityFromFix(*a, x.q_world_imu, bg);
  anchor.sigma_v_fix = a->fix.velocity->sigma_enu.norm();
  return anchor;
}

std::optional<InitialState> StateInitializer::TryInitialize() {
  if (local_.enabled && !local_.enu_later) return TryInitializeLocal();
  if (std::optional<InitialState> enu = TryInitializeEnu()) return enu;
  // With GNSS, a local start only where a GNSS course would come late (or no fix came yet):
  // fixes noisy enough that a course needs a chord longer than course_min_distance_m (15 sigma,
  // CourseReference). Precise fixes give the course after course_min_distance_m, where the
  // local frame's alignment would move into ENU too (gnss_front_end.hpp): a local start would
  // add a frame change and nothing else.
  if (local_.enabled && (fixes_.empty() || !PreciseFixes())) return TryInitializeLocal();
  return std::nullopt;
}

bool StateInitializer::PreciseFixes() const {
  const Mat3& c = fixes_.back().fix.covariance;
  return 15.0 * std::sqrt(c(0, 0) + c(1, 1)) <= options_.course_min_distance_m;
}

std::optional<InitialState> StateInitializer::TryInitializeEnu() {
  if (imu_.empty() || fixes_.empty()) return std::nullopt;
  const InitializationMode mode = options_.mode;
  const bool use_still = still_.has_value() && mode != InitializationMode::kMoving;
  if (mode == InitializationMode::kStatic && !use_still) return std::nullopt;

  std::optional<YawReference> yaw = heading_;
  if (!yaw) yaw = VelocityCourseReference();
  if (!yaw) yaw = CourseReference();
  if (!yaw) return std::nullopt;
  const TimeNs t0 = imu_.back().header.stamp_ns;
  const TimeNs t_imu_begin = imu_.front().header.stamp_ns;
  const TimeNs t_fix = fixes_.back().fix.header.stamp_ns;
  if (yaw->t_ns < t_imu_begin || yaw->t_ns > t0 || t_fix < t_imu_begin || t_fix > t0) {
    return std::nullopt;
  }
  std::optional<Anchor> anchor = use_still ? StaticAnchor(*yaw, t0) : VelocityAnchor(*yaw);
  if (!anchor && !use_still) anchor = MovingAnchor(*yaw);
  if (!anchor) return std::nullopt;

  InitialState out;
  const NavState& x = anchor->state;
  out.state = x.t_ns < t0 ? Preintegrate(x.t_ns, t0, x.gyro_bias).Predict(x) : x;
  out.state.t_ns = t0;
  if (anchor->still_now) out.state.v_world.setZero();

  const InitializationOptions& o = options_;
  const double sigma_v = anchor->still_now
                             ? o.static_velocity_sigma_mps
                             : std::hypot(o.moving_velocity_sigma_mps, anchor->sigma_v_fix);
  const double sigma_bg =
      use_still ? std::max(2.0 * noise_.gyro_noise_density / std::sqrt(o.static_duration_s), 1e-4)
                : o.gyro_bias_sigma_radps;
  const Mat3 R0 = out.state.q_world_imu.toRotationMatrix();
  const double sigma_tilt = anchor->sigma_tilt;
  const Vec3 world_rotation_var(sigma_tilt * sigma_tilt, sigma_tilt * sigma_tilt,
                                yaw->sigma_rad * yaw->sigma_rad);
  const double attitude_sigma = std::max(sigma_tilt, yaw->sigma_rad);
  const Fix& b = fixes_.back();
  const double lever = b.p_imu_antenna.norm() * attitude_sigma;
  const double drift = sigma_v * ToSeconds(t0 - t_fix);
  Mat15& P = out.covariance;
  P.setZero();
  P.block<3, 3>(kRotationIndex, kRotationIndex) =
      R0.transpose() * world_rotation_var.asDiagonal() * R0;
  if (anchor->fit_covariance) {
    // A moving start fitted over its chord: the fit's position at t0 rests on every fix of it,
    // not on the newest alone (p0 = p_a + v_a T + g T^2 / 2 + R_a dp).
    const ImuPreintegration pim = Preintegrate(x.t_ns, t0, x.gyro_bias);
    Eigen::Matrix<double, 3, 9> J;
    J << Mat3::Identity(), ToSeconds(t0 - x.t_ns) * Mat3::Identity(),
        -x.q_world_imu.toRotationMatrix() * so3::Hat(pim.delta_p());
    const Mat3 fitted = J * *anchor->fit_covariance * J.transpose();
    P.block<3, 3>(kPositionIndex, kPositionIndex) = 0.5 * (fitted + fitted.transpose());
  } else {
    P.block<3, 3>(kPositionIndex, kPositionIndex) =
        b.fix.covariance + (lever * lever + drift * drift) * Mat3::Identity();
  }
  P.block<3, 3>(kVelocityIndex, kVelocityIndex) = sigma_v * sigma_v * Mat3::Identity();
  P.block<3, 3>(kGyroBiasIndex, kGyroBiasIndex) = sigma_bg * sigma_bg * Mat3::Identity();
  P.block<3, 3>(kAccelBiasIndex, kAccelBiasIndex) =
      o.accel_bias_sigma_mps2 * o.accel_bias_sigma_mps2 * Mat3::Identity();
  out.method = std::string(use_still ? "static" : "moving") + " (" + yaw->method + ")";
  return out;
}

}  // namespace statebench::est
