// The EKF's propagation, measurement updates (gyro yaw rate, dual-antenna heading, GNSS position
// with the lever arm and Doppler velocity) and its initialisation from the GNSS course. The
// odometry updates are in ekf_odometry_updates.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "estimator/ekf_filter_impl.hpp"

namespace statebench::est {
namespace {

using namespace ekf;  // NOLINT: the state layout (kX, kPsi, ...) and the sensor roles

}  // namespace

void EkfSingleTrackEstimator::Impl::Propagate(TimeNs t_to_ns) {
  if (t_to_ns <= t_ns) return;
  const double total = ToSeconds(t_to_ns - t_ns);
  const int steps = std::max(1, static_cast<int>(std::ceil(total / kMaxSubstepS)));
  const double dt = total / steps;
  VecN qc = VecN::Zero();
  qc[kX] = qc[kY] = options.position_density * options.position_density;
  qc[kVx] = options.accel_noise_density * options.accel_noise_density;
  qc[kVy] = options.lateral_model_density * options.lateral_model_density;
  qc[kR] = options.yaw_accel_density * options.yaw_accel_density;
  qc[kBg] = options.gyro_bias_walk * options.gyro_bias_walk;
  qc[kBa] = options.accel_bias_walk * options.accel_bias_walk;
  for (int k = 0; k < steps; ++k) {
    const MatN F = MatN::Identity() + model->DerivativeJacobian(x, accel_x, steering) * dt;
    const VecN mid = x + 0.5 * dt * model->Derivative(x, accel_x, steering);
    x += dt * model->Derivative(mid, accel_x, steering);
    x[kPsi] = so3::WrapAngle(x[kPsi]);
    P = F * P * F.transpose();
    P.diagonal() += qc * dt;
  }
  Pz += options.altitude_density * options.altitude_density * total;
  t_ns = t_to_ns;
}

void EkfSingleTrackEstimator::Impl::UpdateGyro(double gz_body) {
  Eigen::Matrix<double, 1, kN> H = Eigen::Matrix<double, 1, kN>::Zero();
  H(0, kR) = 1.0;
  H(0, kBg) = 1.0;
  Eigen::Matrix<double, 1, 1> y(gz_body - x[kR] - x[kBg]);
  Eigen::Matrix<double, 1, 1> R(options.gyro_sigma_radps * options.gyro_sigma_radps);
  Update<1>(y, H, R);
}

void EkfSingleTrackEstimator::Impl::UpdateHeading(const std::string& id, const SensorInfo& info,
                                                  const DualAntennaHeading& m) {
  Eigen::Matrix<double, 1, kN> H = Eigen::Matrix<double, 1, kN>::Zero();
  H(0, kPsi) = 1.0;
  Eigen::Matrix<double, 1, 1> y(so3::WrapAngle(m.yaw_rad - (x[kPsi] + info.yaw_offset_rad) -
                                               x[kR] * ToSeconds(m.header.stamp_ns - t_ns)));
  Eigen::Matrix<double, 1, 1> R(m.yaw_sigma_rad * m.yaw_sigma_rad);
  const auto last = last_accepted_heading_ns.find(id);
  if (!Gate(Mahalanobis<1>(y, H, R), options.heading_gate_chi2, m.header.stamp_ns,
            last == last_accepted_heading_ns.end() ? initialized_ns : last->second)) {
    Reject(id, m.header.stamp_ns, RejectReason::kMahalanobisGate);
    return;
  }
  Update<1>(y, H, R);
  last_accepted_heading_ns[id] = m.header.stamp_ns;
  Accept(id, m.header.stamp_ns);
}

void EkfSingleTrackEstimator::Impl::UpdateGnss(const std::string& id, const SensorInfo& info,
                                               const GnssPositionEnu& fix) {
  const auto start = std::chrono::steady_clock::now();
  const Mat3 cov = AdjustedCovariance(fix.covariance, info);
  // Lag: the fix is of stamp_ns <= t_ns; carry the prediction back by the current velocity.
  const double lag = ToSeconds(t_ns - fix.header.stamp_ns);
  const double c = std::cos(x[kPsi]), s = std::sin(x[kPsi]);
  const Vec2 l = info.p_body_sensor.head<2>();
  const Vec2 Rl(c * l.x() - s * l.y(), s * l.x() + c * l.y());
  const Vec2 v_world(c * x[kVx] - s * x[kVy] - x[kR] * Rl.y(),
                     s * x[kVx] + c * x[kVy] + x[kR] * Rl.x());
  const Vec2 predicted = Vec2(x[kX], x[kY]) + Rl - v_world * lag;
  Eigen::Matrix<double, 2, kN> H = Eigen::Matrix<double, 2, kN>::Zero();
  H(0, kX) = 1.0;
  H(1, kY) = 1.0;
  H(0, kPsi) = -Rl.y();
  H(1, kPsi) = Rl.x();
  const Vec2 y = fix.p_enu.head<2>() - predicted;
  const Mat2 R = cov.topLeftCorner<2, 2>();
  const auto last = last_accepted_gnss_ns.find(id);
  const double d2 = Mahalanobis<2>(y, H, R);
  const bool outside = !(d2 <= options.gnss_gate_chi2);
  RefusedFixTrack& refused = refused_fixes[id];
  if (outside) refused.Refused(fix);
  if (!Gate(d2, options.gnss_gate_chi2, fix.header.stamp_ns,
            last == last_accepted_gnss_ns.end() ? initialized_ns : last->second)) {
    Reject(id, fix.header.stamp_ns, RejectReason::kMahalanobisGate);
    return;
  }
  // The gate has refused every fix for gate_reset_s and the refused fixes agree with each other:
  // the filter is off, not the receiver.
  if (outside && refused.Agrees()) {
    Reject(id, fix.header.stamp_ns, RejectReason::kMahalanobisGate);
    StartOver(id, fix.header.stamp_ns, "lost");
    return;
  }
  refused.Clear();
  Update<2>(y, H, R);
  // Altitude of the body origin (flat vehicle: the lever arm's z is a constant offset).
  const double z_meas = fix.p_enu.z() - info.p_body_sensor.z();
  const double k = Pz / (Pz + cov(2, 2));
  z += k * (z_meas - z);
  Pz *= 1.0 - k;
  last_accepted_gnss_ns[id] = fix.header.stamp_ns;
  Accept(id, fix.header.stamp_ns);
  UpdateDiagnostics u;
  u.t_ns = t_ns;
  u.solve_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  u.iterations = 1;
  u.usable = true;
  u.num_states = 1;
  u.factors["gnss"] = 1;
  diag.updates.Add(u);
}

void EkfSingleTrackEstimator::Impl::UpdateGnssVelocity(const std::string& id,
                                                       const SensorInfo& info,
                                                       const GnssPositionEnu& fix) {
  const GnssVelocity& v = *fix.velocity;
  const double c = std::cos(x[kPsi]), s = std::sin(x[kPsi]);
  const Vec2 l = info.p_body_sensor.head<2>();
  const double a = x[kVx] - x[kR] * l.y(), b = x[kVy] + x[kR] * l.x();
  const Vec2 predicted(c * a - s * b, s * a + c * b);
  Eigen::Matrix<double, 2, kN> H = Eigen::Matrix<double, 2, kN>::Zero();
  H(0, kPsi) = -s * a - c * b;
  H(1, kPsi) = c * a - s * b;
  H(0, kVx) = c;
  H(1, kVx) = s;
  H(0, kVy) = -s;
  H(1, kVy) = c;
  H(0, kR) = -(c * l.y() + s * l.x());
  H(1, kR) = c * l.x() - s * l.y();
  const Vec2 y = v.v_enu.head<2>() - predicted;
  const Mat2 R = v.sigma_enu.head<2>().cwiseAbs2().asDiagonal();
  const auto last = last_accepted_velocity_ns.find(id);
  if (!Gate(Mahalanobis<2>(y, H, R), options.gnss_gate_chi2, fix.header.stamp_ns,
            last == last_accepted_velocity_ns.end() ? initialized_ns : last->second)) {
    ++diag.sensors[id].events["velocity_gated"];
    return;
  }
  Update<2>(y, H, R);
  last_accepted_velocity_ns[id] = fix.header.stamp_ns;
  ++diag.sensors[id].events["velocity_updates"];
}

void EkfSingleTrackEstimator::Impl::TryInitialize(const std::string& id, const SensorInfo& info,
                                                  const GnssPositionEnu& fix) {
  if (id != course_antenna) return;
  const Mat3 cov_now = AdjustedCovariance(fix.covariance, info);
  std::optional<EkfCourseStart::Course> course =
      course_start.AddFix(fix.header.stamp_ns, fix.p_enu, cov_now, options.course_min_distance_m,
                          options.course_max_yaw_sigma_rad);
  // The receiver's Doppler velocity, when it gives one, starts sooner and points better.
  const std::optional<EkfCourseStart::Course> velocity_course =
      fix.velocity ? EkfCourseStart::FromVelocity(fix.velocity->v_enu.head<2>(),
                                                  fix.velocity->sigma_enu.head<2>().maxCoeff(),
                                                  info.p_body_sensor, gyro_z,
                                                  options.velocity_course_min_speed_mps)
                   : std::nullopt;
  const char* how = "moving (gnss course)";
  if (velocity_course && (!course || velocity_course->yaw_variance < course->yaw_variance)) {
    course = velocity_course;
    how = "moving (gnss velocity)";
  }
  if (!course) return;
  double yaw = course->yaw_rad;
  double speed = course->speed_mps;
  double speed_variance = course->speed_variance;
  if (encoder_speed) {
    speed = *encoder_speed;
    speed_variance = 0.0;
    if (speed < 0.0) yaw = so3::WrapAngle(yaw + std::numbers::pi);
  }
  const double course_var = course->yaw_variance;
  const Mat3& cov = cov_now;
  const Vec2 Rl = (YawRotation(yaw) * info.p_body_sensor).head<2>();
  x = VecN::Zero();
  x[kX] = fix.p_enu.x() - Rl.x();
  x[kY] = fix.p_enu.y() - Rl.y();
  x[kPsi] = yaw;
  x[kVx] = speed;
  P = MatN::Zero();
  P.topLeftCorner<2, 2>() = cov.topLeftCorner<2, 2>();
  P(kPsi, kPsi) = options.init_yaw_sigma_rad * options.init_yaw_sigma_rad + course_var;
  // The lever arm moves the yaw uncertainty into the position.
  const Vec2 dpos_dpsi(-Rl.y(), Rl.x());
  P.block<2, 1>(0, kPsi) = -dpos_dpsi * P(kPsi, kPsi);
  P.block<1, 2>(kPsi, 0) = P.block<2, 1>(0, kPsi).transpose();
  P.topLeftCorner<2, 2>() += dpos_dpsi * dpos_dpsi.transpose() * P(kPsi, kPsi);
  P(kVx, kVx) = options.init_speed_sigma_mps * options.init_speed_sigma_mps + speed_variance;
  P(kVy, kVy) = options.init_speed_sigma_mps * options.init_speed_sigma_mps;
  P(kR, kR) = 0.1 * 0.1;
  P(kBg, kBg) = options.init_gyro_bias_sigma_radps * options.init_gyro_bias_sigma_radps;
  P(kBa, kBa) = options.init_accel_bias_sigma_mps2 * options.init_accel_bias_sigma_mps2;
  z = fix.p_enu.z() - info.p_body_sensor.z();
  Pz = cov(2, 2);
  t_ns = fix.header.stamp_ns;
  initialized = true;
  initialized_ns = t_ns;
  diag.Initialized(t_ns, how);
  if (last_imu_ns) {
    Propagate(*last_imu_ns);
    PushHistory();
  }
}

void EkfSingleTrackEstimator::Impl::StartOver(const std::string& id, TimeNs stamp_ns,
                                              const char* event) {
  diag.Lost(stamp_ns, event);
  ++diag.sensors[id].events[event];
  initialized = false;
  course_start.Reset();
  history.clear();
  refused_fixes.clear();
  last_accepted_gnss_ns.clear();
  last_accepted_speed_ns.clear();
  last_accepted_heading_ns.clear();
  odometry_zero_since_ns.reset();
  standstill_imu.clear();
  still_imu.Clear();
  doppler.Clear();
  next_zero_velocity_ns = INT64_MIN;
  if (local_start) ResetLocalStart();  // a new local frame from the next start
}

}  // namespace statebench::est

namespace statebench::est {

std::string EkfSingleTrackEstimator::Impl::WaitingFor() const {
  if (!last_imu_ns) return "no IMU sample";
  if (!course_start.has_fix()) return "no GNSS fix of " + course_antenna;
  char text[200];
  std::snprintf(text, sizeof(text),
                "no GNSS course (the longest chord of %s's last %.0f s is %.3g m of the %.3g m "
                "needed)",
                course_antenna.c_str(), EkfCourseStart::kHistoryS, course_start.longest_chord_m(),
                course_start.needed_m());
  return text;
}

}  // namespace statebench::est
