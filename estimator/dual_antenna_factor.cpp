#include "estimator/dual_antenna_factor.hpp"

#include <string>

#include "core/error.hpp"

namespace statebench::est {

DualAntennaFactor::DualAntennaFactor(const DualAntennaHeading& m, const Vec3& p_imu_main,
                                     const Vec3& p_imu_aux, const Quat& q_imu_i_imu_t)
    : raw_baseline_imu_(p_imu_aux - p_imu_main),
      pitch_axis_imu_(PitchAxis(raw_baseline_imu_)),
      q_imu_i_imu_t_(q_imu_i_imu_t.normalized()),
      baseline_imu_(q_imu_i_imu_t_ * raw_baseline_imu_),
      yaw_rad_(m.yaw_rad),
      pitch_rad_(m.pitch_rad),
      yaw_sigma_rad_(m.yaw_sigma_rad),
      pitch_sigma_rad_(m.pitch_sigma_rad),
      use_pitch_(std::isfinite(m.pitch_sigma_rad) && m.pitch_sigma_rad > 0.0 &&
                 std::isfinite(m.pitch_rad)) {
  const std::string where = "dual antenna factor (" + m.header.sensor_id + "): ";
  if (!std::isfinite(m.yaw_rad) || !std::isfinite(m.yaw_sigma_rad) || m.yaw_sigma_rad <= 0.0) {
    throw InputError(where + "yaw and a positive yaw sigma are required");
  }
  if (!baseline_imu_.allFinite() || baseline_imu_.norm() < 0.01 ||
      baseline_imu_.head<2>().norm() < 1e-3 * baseline_imu_.norm()) {
    throw InputError(where +
                     "baseline between the antennas must be at least 1 cm and not vertical");
  }
}

}  // namespace statebench::est
