// What an imperfect calibration adds to the uncertainty of a GNSS measurement.
//
// The setup gives each sensor's mount (T_body_sensor) and latency as measured; a real vehicle's
// are off by about 1-2 cm and 0.2-1 deg when measured by hand, and unsynchronised clocks by a
// few ms (shared/REFERENCE.md, "Real units are not their datasheet"). The estimator does not
// estimate these; it widens the measurements they corrupt by what they can do there:
//  - position fix, antenna lever arm l (IMU frame), IMU attitude R, velocity v (world):
//      lever arm translation: both mounts (IMU and antenna) off by sigma_t per axis
//                             -> 2 sigma_t^2 I;
//      IMU mount rotation:    the lever arm turned by an angle of sigma_r per axis
//                             -> sigma_r^2 (|l|^2 I - (R l)(R l)^T);
//      clock offset:          the fix belongs to t + dt -> sigma_c^2 v v^T;
//  - dual-antenna heading, baseline b (IMU frame): two antenna mounts across the baseline turn
//    it by 2 sigma_t^2 / |b_horizontal|^2 (rad^2) in yaw (and by the same over |b| in pitch), and
//    the IMU mount rotation adds sigma_r^2 to both.
// These errors are constant for a vehicle, not white: widening every measurement by them keeps
// the smoother from fitting them, but the smoother then averages them down over its fixes as
// if they were noise. What averaging cannot remove is added to the output covariance instead
// (CalibrationConsiderCovariance: Schmidt's "consider" covariance of unestimated constant
// parameters, here with their direct effect on the state): the antenna's position error carries
// into the position, and a heading baseline's error into the yaw. The mean is not changed.
// Estimating the calibration as states is the full answer.
#pragma once

#include "core/eigen_types.hpp"
#include "core/state.hpp"
#include "estimator/estimator_config.hpp"

namespace statebench::est {

// Covariance (world frame, m^2) to add to a position fix of the antenna at p_imu_antenna.
Mat3 PositionCalibrationCovariance(const GnssCalibrationUncertainty& u, const Quat& q_world_imu,
                                   const Vec3& v_world, const Vec3& p_imu_antenna);

struct HeadingCalibrationVariance {
  double yaw_rad2 = 0.0;
  double pitch_rad2 = 0.0;
};
// Variances to add to a dual-antenna heading with the baseline main -> aux (IMU frame).
HeadingCalibrationVariance HeadingCalibration(const GnssCalibrationUncertainty& u,
                                              const Vec3& baseline_imu);

// The output's share of the calibration errors (15x15, core/state.hpp order; rotation as the
// right perturbation): the position block from the antenna at p_imu_antenna (as a fix), and,
// when the yaw comes from a heading baseline (main -> aux, IMU frame), that baseline's yaw
// variance about the world's vertical and, when the baseline also measures pitch
// (baseline_pitch), its pitch variance about the horizontal axis across it.
Mat15 CalibrationConsiderCovariance(const GnssCalibrationUncertainty& u, const NavState& state,
                                    const Vec3& p_imu_antenna, const Vec3* baseline_imu,
                                    bool baseline_pitch = false);

// Motion constraints in the body frame (non-holonomic: the velocity along the body's forward
// axis) tie the IMU's attitude to the body as the setup gives it (q_body_imu); an IMU mount
// turned by mount_rotation_sigma_deg about the body's vertical or lateral axis turns the
// estimated yaw or pitch by as much. The rotation block (right perturbation) of that share.
Mat3 MotionConstraintConsiderCovariance(const GnssCalibrationUncertainty& u,
                                        const Quat& q_body_imu);

// What a factor graph's output adds for the calibration it does not estimate: the first
// antenna's lever arm (CalibrationConsiderCovariance), the first heading pair's baseline (yaw,
// and pitch once a heading with a pitch was accepted: heading_pitch_seen) unless the smoother
// estimates it (gnss_calibration.estimate_heading_baseline), and the motion constraints' share
// unless the non-holonomic constraint estimates the IMU mount. Zero without an antenna.
Mat15 OutputCalibrationConsider(const EstimatorSensorSetup& setup,
                                const FactorGraphOptions& options, bool heading_pitch_seen,
                                const NavState& state);

}  // namespace statebench::est
