#include "estimator/gnss_calibration_covariance.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::est {
namespace {

double Radians(double deg) { return deg * M_PI / 180.0; }

}  // namespace

Mat3 PositionCalibrationCovariance(const GnssCalibrationUncertainty& u, const Quat& q_world_imu,
                                   const Vec3& v_world, const Vec3& p_imu_antenna) {
  const double st = u.mount_translation_sigma_m;
  const double sr = Radians(u.mount_rotation_sigma_deg);
  const double sc = u.clock_offset_sigma_s;
  const Vec3 l_world = q_world_imu * p_imu_antenna;
  Mat3 C = 2.0 * st * st * Mat3::Identity();
  C += sr * sr * (l_world.squaredNorm() * Mat3::Identity() - l_world * l_world.transpose());
  C += sc * sc * v_world * v_world.transpose();
  return C;
}

HeadingCalibrationVariance HeadingCalibration(const GnssCalibrationUncertainty& u,
                                              const Vec3& baseline_imu) {
  const double st = u.mount_translation_sigma_m;
  const double sr = Radians(u.mount_rotation_sigma_deg);
  // A baseline shorter than 1 cm is refused elsewhere; the floor only keeps this finite.
  const double horizontal = std::max(baseline_imu.head<2>().norm(), 0.01);
  const double length = std::max(baseline_imu.norm(), 0.01);
  return {2.0 * st * st / (horizontal * horizontal) + sr * sr,
          2.0 * st * st / (length * length) + sr * sr};
}

Mat15 CalibrationConsiderCovariance(const GnssCalibrationUncertainty& u, const NavState& state,
                                    const Vec3& p_imu_antenna, const Vec3* baseline_imu,
                                    bool baseline_pitch) {
  Mat15 C = Mat15::Zero();
  C.block<3, 3>(3, 3) =
      PositionCalibrationCovariance(u, state.q_world_imu, state.v_world, p_imu_antenna);
  if (baseline_imu != nullptr) {
    const HeadingCalibrationVariance v = HeadingCalibration(u, *baseline_imu);
    // An error d about a world axis a is the right perturbation R^T a d.
    const Vec3 yaw_axis = state.q_world_imu.conjugate() * Vec3::UnitZ();
    Mat3 rotation = v.yaw_rad2 * yaw_axis * yaw_axis.transpose();
    const Vec3 across = Vec3::UnitZ().cross(state.q_world_imu * *baseline_imu);
    if (baseline_pitch && across.norm() > 1e-3) {
      const Vec3 pitch_axis = state.q_world_imu.conjugate() * across.normalized();
      rotation += v.pitch_rad2 * pitch_axis * pitch_axis.transpose();
    }
    C.block<3, 3>(0, 0) = rotation;
  }
  return C;
}

Mat3 MotionConstraintConsiderCovariance(const GnssCalibrationUncertainty& u,
                                        const Quat& q_body_imu) {
  const double sr = Radians(u.mount_rotation_sigma_deg);
  const Vec3 up = q_body_imu.conjugate() * Vec3::UnitZ();  // body axes in the IMU frame
  const Vec3 left = q_body_imu.conjugate() * Vec3::UnitY();
  return sr * sr * (up * up.transpose() + left * left.transpose());
}

Mat15 OutputCalibrationConsider(const EstimatorSensorSetup& setup,
                                const FactorGraphOptions& options, bool heading_pitch_seen,
                                const NavState& state) {
  if (setup.antennas.empty()) return Mat15::Zero();
  Vec3 baseline;
  const Vec3* b = nullptr;
  bool pitch = false;
  if (!setup.dual_antennas.empty() && !options.gnss_calibration.estimate_heading_baseline) {
    const DualAntennaPair& pair = setup.dual_antennas.front();
    baseline = pair.p_imu_aux - pair.p_imu_main;
    b = &baseline;
    pitch = heading_pitch_seen;
  }
  Mat15 C = CalibrationConsiderCovariance(options.gnss_calibration, state,
                                          setup.antennas.front().p_imu_antenna, b, pitch);
  // The motion constraints align the velocity with the vehicle frame as the setup gives it,
  // unless the non-holonomic constraint estimates the IMU mount (the kinematic factor, which
  // replaces it while the encoders run, is turned by the same globals then).
  const NonHolonomicOptions& nhc = options.non_holonomic;
  if (nhc.enabled && !nhc.estimate_mount) {
    C.topLeftCorner<3, 3>() +=
        MotionConstraintConsiderCovariance(options.gnss_calibration, setup.T_body_imu.rotation());
  }
  return C;
}

}  // namespace statebench::est
