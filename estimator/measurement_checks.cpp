#include "estimator/measurement_checks.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <numbers>

namespace statebench::est {

std::optional<RejectReason> CheckImuSample(const ImuSample& sample) {
  if (!sample.gyro.allFinite() || !sample.accel.allFinite()) return RejectReason::kNonFinite;
  if (sample.gyro.cwiseAbs().maxCoeff() > kMaxAbsGyroRadps ||
      sample.accel.cwiseAbs().maxCoeff() > kMaxAbsAccelMps2) {
    return RejectReason::kAbsurdValue;
  }
  return std::nullopt;
}

std::optional<RejectReason> CheckImuLimits(const ImuSample& sample, const ImuLimits& limits) {
  if (sample.gyro.cwiseAbs().maxCoeff() > limits.max_gyro_radps ||
      sample.accel.cwiseAbs().maxCoeff() > limits.max_accel_mps2) {
    return RejectReason::kSaturated;
  }
  return std::nullopt;
}

OptionTable<ImuLimits> ImuLimitsOptionTable() {
  OptionTable<ImuLimits> t("imu limits");
  const OptionRange p = OptionRange::Positive();
  t.Number("max_accel_mps2", &ImuLimits::max_accel_mps2, p,
           "reject samples beyond (per axis; saturated or implausible)")
      .Number("max_gyro_radps", &ImuLimits::max_gyro_radps, p,
              "reject samples beyond (per axis; saturated or implausible)")
      .Number("max_gap_s", &ImuLimits::max_gap_s, p,
              "a longer pause of the IMU stream: start over from the sensors");
  return t;
}

std::optional<RejectReason> CheckGnssFix(const GnssFix& fix) {
  if (!std::isfinite(fix.latitude_deg) || !std::isfinite(fix.longitude_deg) ||
      !std::isfinite(fix.altitude_m) || !fix.covariance_enu.allFinite()) {
    return RejectReason::kNonFinite;
  }
  if (std::abs(fix.latitude_deg) > 90.0 || std::abs(fix.longitude_deg) > 180.0 ||
      fix.altitude_m < -1000.0 || fix.altitude_m > 100000.0) {
    return RejectReason::kAbsurdValue;
  }
  if (fix.status == GnssFixStatus::kNone) return RejectReason::kNoFix;
  const Mat3& cov = fix.covariance_enu;
  if ((cov - cov.transpose()).cwiseAbs().maxCoeff() > 1e-9 * cov.cwiseAbs().maxCoeff() ||
      Eigen::LLT<Mat3>(cov).info() != Eigen::Success) {
    return RejectReason::kInvalidCovariance;
  }
  return std::nullopt;
}

std::optional<RejectReason> CheckDualAntennaHeading(const DualAntennaHeading& heading) {
  if (!std::isfinite(heading.yaw_rad) || !std::isfinite(heading.pitch_rad) ||
      std::isnan(heading.yaw_sigma_rad) || std::isnan(heading.pitch_sigma_rad)) {
    return RejectReason::kNonFinite;
  }
  if (std::abs(heading.pitch_rad) > std::numbers::pi / 2) return RejectReason::kAbsurdValue;
  if (!(heading.yaw_sigma_rad > 0.0) || !std::isfinite(heading.yaw_sigma_rad)) {
    return RejectReason::kInvalidCovariance;
  }
  return std::nullopt;
}

std::optional<RejectReason> CheckVehicleSpeed(const VehicleSpeed& speed) {
  if (!std::isfinite(speed.speed_mps)) return RejectReason::kNonFinite;
  if (std::abs(speed.speed_mps) > 100.0) return RejectReason::kAbsurdValue;
  return std::nullopt;
}

std::optional<RejectReason> CheckSteeringAngle(const SteeringAngle& angle) {
  if (!std::isfinite(angle.angle_rad)) return RejectReason::kNonFinite;
  if (std::abs(angle.angle_rad) > 1.2) return RejectReason::kAbsurdValue;
  return std::nullopt;
}

std::optional<RejectReason> CheckBodyVelocity(const BodyVelocity& v) {
  if (!v.velocity.allFinite() || !v.angular_velocity.allFinite() || !v.covariance.allFinite()) {
    return RejectReason::kNonFinite;
  }
  if (v.velocity.norm() > 100.0) return RejectReason::kAbsurdValue;
  if ((v.covariance.diagonal().head<3>().array() <= 0.0).any()) {
    return RejectReason::kInvalidCovariance;
  }
  return std::nullopt;
}

std::optional<RejectReason> CheckLidarScan(const LidarScan& scan) {
  if (scan.points == nullptr) return RejectReason::kAbsurdValue;
  return std::nullopt;
}

}  // namespace statebench::est
