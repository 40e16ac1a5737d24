// Dual-antenna yaw/pitch factor on the orientation of one state.
//
// The receiver reports the direction of the baseline b from the main to the auxiliary antenna
// in ENU (sensors/dual_antenna_heading.hpp, core DualAntennaHeading):
//   yaw = atan2(b_north, b_east),   pitch = atan2(-b_up, |b_horizontal|)
// (the so3::ToRollPitchYaw convention, pitch positive nose down). The prediction rotates the
// body baseline b_imu = p_imu_aux - p_imu_main with the state orientation, b = R_world_imu b_imu,
// so any mounting direction works, not only a baseline along +x. Residual (2):
//   r = (wrap(yaw(b) - yaw_meas) / sigma_yaw, (pitch(b) - pitch_meas) / sigma_pitch)
// The yaw difference is wrapped with atan2(sin d, cos d) (smooth, so differentiable at +-pi).
// A non-positive or non-finite pitch sigma means "yaw only": the pitch residual is 0.
// A heading taken at t between states is attached to state i (t_i <= t) with the IMU rotation
// delta dR = R_i^T R_t from the preintegration over [t_i, t]: b = R_i dR b_imu. Its bias
// correction is neglected (gyro bias error times t - t_i, 1e-5 rad over 10 ms).
// Parameter block: q_world_imu(4, RightQuaternionManifold). Automatic differentiation.
#pragma once

#include <ceres/autodiff_cost_function.h>

#include <cmath>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"

namespace statebench::est {

class DualAntennaFactor {
 public:
  DualAntennaFactor(const DualAntennaHeading& measurement, const Vec3& p_imu_main,
                    const Vec3& p_imu_aux, const Quat& q_imu_i_imu_t = Quat::Identity());

  template <typename T>
  bool operator()(const T* q_world_imu, T* residuals) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Eigen::Quaternion<T> q = Eigen::Map<const Eigen::Quaternion<T>>(q_world_imu).normalized();
    const Eigen::Matrix<T, 3, 1> b = q * baseline_imu_.cast<T>();
    const T horizontal = sqrt(b.x() * b.x() + b.y() * b.y());
    const T yaw_error = atan2(b.y(), b.x()) - T(yaw_rad_);
    residuals[0] = atan2(sin(yaw_error), cos(yaw_error)) / T(yaw_sigma_rad_);
    residuals[1] =
        use_pitch_ ? (atan2(-b.z(), horizontal) - T(pitch_rad_)) / T(pitch_sigma_rad_) : T(0);
    return true;
  }

  // Throws InputError if the yaw sigma is not positive and finite, an angle is not finite, or
  // the baseline is shorter than 1 cm or vertical in the body frame.
  static ceres::CostFunction* Create(const DualAntennaHeading& measurement, const Vec3& p_imu_main,
                                     const Vec3& p_imu_aux,
                                     const Quat& q_imu_i_imu_t = Quat::Identity()) {
    return new ceres::AutoDiffCostFunction<DualAntennaFactor, 2, 4>(
        new DualAntennaFactor(measurement, p_imu_main, p_imu_aux, q_imu_i_imu_t));
  }

 private:
  Vec3 baseline_imu_;  // main -> aux, in the IMU frame of the state (rotated by dR)
  double yaw_rad_;
  double pitch_rad_;
  double yaw_sigma_rad_;
  double pitch_sigma_rad_;
  bool use_pitch_;
};

}  // namespace statebench::est
