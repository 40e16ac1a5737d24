// StateInitializer: the start of a setup without an absolute-position sensor, in a local frame
// (state_initializer.hpp).
#include <algorithm>
#include <cmath>

#include "estimator/state_initializer.hpp"

namespace statebench::est {

std::optional<OdometryAlignment> StateInitializer::AlignOverOdometryWindow() const {
  const TimeNs t_imu_begin = imu_.front().header.stamp_ns;
  const TimeNs t_imu_end = imu_.back().header.stamp_ns;
  // The newest odometry sample the IMU covers, and those within kOdometryWindowS before it.
  auto end = odometry_.end();
  while (end != odometry_.begin() && std::prev(end)->t_ns > t_imu_end) --end;
  if (end == odometry_.begin()) return std::nullopt;
  const TimeNs t_b = std::prev(end)->t_ns;
  auto begin = end;
  while (begin != odometry_.begin() &&
         std::prev(begin)->t_ns >= t_b - FromSeconds(kOdometryWindowS) &&
         std::prev(begin)->t_ns >= t_imu_begin) {
    --begin;
  }
  if (begin == end || t_b - begin->t_ns < FromSeconds(0.9 * kOdometryWindowS)) return std::nullopt;
  const std::vector<OdometryVelocity> window(begin, end);
  return AlignWithOdometry(imu_, window, noise_, Vec3::Zero());
}

std::optional<InitialState> StateInitializer::TryInitializeLocal() {
  if (imu_.empty()) return std::nullopt;
  const InitializationOptions& o = options_;
  const bool use_still = still_.has_value() && o.mode != InitializationMode::kMoving;
  if (o.mode == InitializationMode::kStatic && !use_still) return std::nullopt;
  const TimeNs t0 = imu_.back().header.stamp_ns;

  // The state at the stamp the data give it (before yaw and position are fixed), in a frame
  // whose z axis is up.
  NavState x;
  double sigma_tilt = 0.0;
  double sigma_bg = 0.0;
  Mat3 velocity_covariance;  // world frame
  TimeNs t_data = 0;         // the newest stamp the velocity rests on
  std::string method;
  if (use_still) {
    x.t_ns = t_data = still_->t_ns;
    x.q_world_imu = Quat::FromTwoVectors(still_->up_imu, Vec3::UnitZ());
    x.gyro_bias = still_->gyro_bias;
    sigma_tilt = o.roll_pitch_sigma_rad;
    sigma_bg = std::max(2.0 * noise_.gyro_noise_density / std::sqrt(o.static_duration_s), 1e-4);
    velocity_covariance =
        o.static_velocity_sigma_mps * o.static_velocity_sigma_mps * Mat3::Identity();
    method = "static (local frame)";
  } else {
    if (!odometry_since_fit_) return std::nullopt;
    // Odometry reading zero: a still period gives the gyro bias as well, so the odometry fit
    // waits until the IMU has had static_duration_s to show one (it does not with an engine
    // running, for example).
    const TimeNs t_odometry = odometry_.back().t_ns;
    if (o.mode == InitializationMode::kAuto &&
        t0 - imu_.front().header.stamp_ns < FromSeconds(o.static_duration_s) &&
        OdometryProvesStandstill(t_odometry - FromSeconds(kOdometryWindowS), t_odometry)) {
      return std::nullopt;
    }
    odometry_since_fit_ = false;
    const std::optional<OdometryAlignment> fit = AlignOverOdometryWindow();
    if (!fit) return std::nullopt;
    if (std::abs(fit->gravity_mps2 - kGravity) > kMaxStillGravityError) {
      fit_gravity_ = fit->gravity_mps2;  // e.g. wheel slip over the window
      return std::nullopt;
    }
    x.t_ns = fit->t_a_ns;
    x.q_world_imu = Quat::FromTwoVectors(fit->up_imu, Vec3::UnitZ());
    x.v_world = x.q_world_imu * fit->u_imu;
    // The velocity at the window's last odometry stamp rests on u_a + tau G; its covariance from
    // the fit, doubled in sigma (the accel bias and the unmeasured components' zero are models).
    t_data = fit->t_b_ns;
    Eigen::Matrix<double, 3, 6> J;
    J << Mat3::Identity(), ToSeconds(t_data - x.t_ns) * Mat3::Identity();
    const Mat3 R_a = x.q_world_imu.toRotationMatrix();
    velocity_covariance =
        4.0 * R_a * J * fit->covariance * J.transpose() * R_a.transpose() +
        o.static_velocity_sigma_mps * o.static_velocity_sigma_mps * Mat3::Identity();
    sigma_tilt = o.moving_roll_pitch_sigma_rad;
    sigma_bg = o.gyro_bias_sigma_radps;
    method = "moving (odometry, local frame)";
  }

  InitialState out;
  out.state = x.t_ns < t0 ? Preintegrate(x.t_ns, t0, x.gyro_bias).Predict(x) : x;
  out.state.t_ns = t0;
  // The local frame: the vehicle's forward axis along x and the IMU at the origin at t0 (a
  // rotation of the whole state about the vertical).
  const Vec3 forward_world = out.state.q_world_imu * forward_imu_;
  const Quat q_yaw(
      Eigen::AngleAxisd(-std::atan2(forward_world.y(), forward_world.x()), Vec3::UnitZ()));
  out.state.q_world_imu = (q_yaw * out.state.q_world_imu).normalized();
  out.state.v_world = q_yaw * out.state.v_world;
  out.state.p_world.setZero();
  const Mat3 R_yaw = q_yaw.toRotationMatrix();
  // Carried by the IMU alone since t_data: the tilt and accel bias errors integrate.
  const double drift = (sigma_tilt * kGravity + o.accel_bias_sigma_mps2) * ToSeconds(t0 - t_data);
  velocity_covariance =
      R_yaw * velocity_covariance * R_yaw.transpose() + drift * drift * Mat3::Identity();

  const Mat3 R0 = out.state.q_world_imu.toRotationMatrix();
  const Vec3 world_rotation_var(sigma_tilt * sigma_tilt, sigma_tilt * sigma_tilt,
                                kLocalYawSigmaRad * kLocalYawSigmaRad);
  Mat15& P = out.covariance;
  P.setZero();
  P.block<3, 3>(kRotationIndex, kRotationIndex) =
      R0.transpose() * world_rotation_var.asDiagonal() * R0;
  P.block<3, 3>(kPositionIndex, kPositionIndex) =
      kLocalPositionSigmaM * kLocalPositionSigmaM * Mat3::Identity();
  P.block<3, 3>(kVelocityIndex, kVelocityIndex) = velocity_covariance;
  P.block<3, 3>(kGyroBiasIndex, kGyroBiasIndex) = sigma_bg * sigma_bg * Mat3::Identity();
  P.block<3, 3>(kAccelBiasIndex, kAccelBiasIndex) =
      o.accel_bias_sigma_mps2 * o.accel_bias_sigma_mps2 * Mat3::Identity();
  out.method = method;
  out.local_frame = true;
  return out;
}

}  // namespace statebench::est
