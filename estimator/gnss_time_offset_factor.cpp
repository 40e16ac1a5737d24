#include "estimator/gnss_time_offset_factor.hpp"

#include "core/so3.hpp"
#include "estimator/so3_manifold.hpp"

namespace statebench::est {

GnssTimeOffsetFactor::GnssTimeOffsetFactor(const Vec3& p_enu_measured, const Mat3& covariance_enu,
                                           const Vec3& p_imu_antenna,
                                           ImuPreintegration propagation,
                                           const Quat& q_world_imu_lin,
                                           const Vec3& omega_raw_imu)
    : position_(p_enu_measured, covariance_enu, p_imu_antenna, std::move(propagation),
                q_world_imu_lin),
      lever_velocity_i_(position_.propagation().delta_v() +
                        position_.propagation().delta_R() *
                            (omega_raw_imu - position_.propagation().bias_lin().gyro)
                                .cross(p_imu_antenna)) {}

bool GnssTimeOffsetFactor::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  if (!position_.Evaluate(parameters, residuals, jacobians)) return false;
  const Mat3 R_i = Eigen::Map<const Quat>(parameters[0]).normalized().toRotationMatrix();
  const Eigen::Map<const Vec3> v_i(parameters[2]);
  const double tau = position_.propagation().dt();
  const double d = parameters[4][0];
  const Mat3& S = position_.sqrt_information();
  const Vec3 v_antenna = v_i + kGravityWorld * tau + R_i * lever_velocity_i_;
  Eigen::Map<Vec3>{residuals} -= d * (S * v_antenna);
  if (jacobians == nullptr) return true;
  using RowMajor3x3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  using RowMajor3x4 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
  if (jacobians[0] != nullptr) {
    Eigen::Map<RowMajor3x4>{jacobians[0]} +=
        d * S * R_i * so3::Hat<double>(lever_velocity_i_) * QuaternionMinusJacobian(parameters[0]);
  }
  if (jacobians[2] != nullptr) Eigen::Map<RowMajor3x3>{jacobians[2]} -= d * S;
  if (jacobians[4] != nullptr) Eigen::Map<Vec3>{jacobians[4]} = -S * v_antenna;
  return true;
}

}  // namespace statebench::est
