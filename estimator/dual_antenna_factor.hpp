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
// With the baseline's direction error as two globals (CreateWithBaselineCorrection: yaw c_y and
// pitch c_p, rad, blocks after q): the setup's baseline b_imu, measured by hand, is turned first
// by c_p about the horizontal axis across it (IMU z x b_imu) and then by c_y about the IMU's z,
//   b_imu' = Rz(c_y) Ra(c_p) b_imu,
// so a positive c_y adds c_y to the predicted yaw and a positive c_p to the pitch (a level
// baseline); the IMU rotation delta dR turns b_imu' as it turns b_imu.
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
    return Residual(q_world_imu, baseline_imu_.cast<T>().eval(), residuals);
  }

  template <typename T>
  bool operator()(const T* q_world_imu, const T* c_yaw, const T* c_pitch, T* residuals) const {
    const Eigen::Matrix<T, 3, 1> b =
        Turned<T>(raw_baseline_imu_.cast<T>(), pitch_axis_imu_.cast<T>(), *c_yaw, *c_pitch);
    return Residual(q_world_imu, (q_imu_i_imu_t_.cast<T>() * b).eval(), residuals);
  }

  // Throws InputError if the yaw sigma is not positive and finite, an angle is not finite, or
  // the baseline is shorter than 1 cm or vertical in the body frame.
  static ceres::CostFunction* Create(const DualAntennaHeading& measurement, const Vec3& p_imu_main,
                                     const Vec3& p_imu_aux,
                                     const Quat& q_imu_i_imu_t = Quat::Identity()) {
    return new ceres::AutoDiffCostFunction<DualAntennaFactor, 2, 4>(
        new DualAntennaFactor(measurement, p_imu_main, p_imu_aux, q_imu_i_imu_t));
  }
  // Blocks q_world_imu(4), c_yaw(1), c_pitch(1).
  static ceres::CostFunction* CreateWithBaselineCorrection(
      const DualAntennaHeading& measurement, const Vec3& p_imu_main, const Vec3& p_imu_aux,
      const Quat& q_imu_i_imu_t = Quat::Identity()) {
    return new ceres::AutoDiffCostFunction<DualAntennaFactor, 2, 4, 1, 1>(
        new DualAntennaFactor(measurement, p_imu_main, p_imu_aux, q_imu_i_imu_t));
  }

  // The baseline (IMU frame) turned by the corrections as the factor turns it.
  static Vec3 TurnedBaseline(const Vec3& baseline_imu, double c_yaw, double c_pitch) {
    return Turned<double>(baseline_imu, PitchAxis(baseline_imu), c_yaw, c_pitch);
  }

 private:
  // The axis the pitch correction turns the baseline about: horizontal in the IMU frame, across
  // the baseline (IMU z x b, unit).
  static Vec3 PitchAxis(const Vec3& baseline_imu) {
    return Vec3::UnitZ().cross(baseline_imu).normalized();
  }
  // Rodrigues about the unit axis a (a . b = 0) by c_pitch, then about z by c_yaw.
  template <typename T>
  static Eigen::Matrix<T, 3, 1> Turned(const Eigen::Matrix<T, 3, 1>& b,
                                       const Eigen::Matrix<T, 3, 1>& a, const T& c_yaw,
                                       const T& c_pitch) {
    using std::cos;
    using std::sin;
    const Eigen::Matrix<T, 3, 1> b_p = b * cos(c_pitch) + a.cross(b) * sin(c_pitch);
    return Eigen::Matrix<T, 3, 1>(b_p.x() * cos(c_yaw) - b_p.y() * sin(c_yaw),
                                  b_p.x() * sin(c_yaw) + b_p.y() * cos(c_yaw), b_p.z());
  }

  template <typename T>
  bool Residual(const T* q_world_imu, const Eigen::Matrix<T, 3, 1>& baseline_imu,
                T* residuals) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Eigen::Quaternion<T> q = Eigen::Map<const Eigen::Quaternion<T>>(q_world_imu).normalized();
    const Eigen::Matrix<T, 3, 1> b = q * baseline_imu;
    const T horizontal = sqrt(b.x() * b.x() + b.y() * b.y());
    const T yaw_error = atan2(b.y(), b.x()) - T(yaw_rad_);
    residuals[0] = atan2(sin(yaw_error), cos(yaw_error)) / T(yaw_sigma_rad_);
    residuals[1] =
        use_pitch_ ? (atan2(-b.z(), horizontal) - T(pitch_rad_)) / T(pitch_sigma_rad_) : T(0);
    return true;
  }

  Vec3 raw_baseline_imu_;  // main -> aux as the setup gives it
  Vec3 pitch_axis_imu_;    // unit, IMU z x raw baseline
  Quat q_imu_i_imu_t_;     // dR
  Vec3 baseline_imu_;      // main -> aux, in the IMU frame of the state (rotated by dR)
  double yaw_rad_;
  double pitch_rad_;
  double yaw_sigma_rad_;
  double pitch_sigma_rad_;
  bool use_pitch_;
};

}  // namespace statebench::est
