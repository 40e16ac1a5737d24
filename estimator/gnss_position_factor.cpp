#include "estimator/gnss_position_factor.hpp"

#include "core/so3.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/sqrt_information.hpp"

namespace statebench::est {

GnssPositionFactor::GnssPositionFactor(const Vec3& p_enu_measured, const Mat3& covariance_enu,
                                       const Vec3& p_imu_antenna)
    : p_enu_measured_(p_enu_measured),
      p_imu_antenna_(p_imu_antenna),
      sqrt_information_(SqrtInformation<3>(covariance_enu, "gnss position factor")) {}

bool GnssPositionFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  const Quat q = Eigen::Map<const Quat>(parameters[0]).normalized();
  const Eigen::Map<const Vec3> p(parameters[1]);
  const Mat3 R = q.toRotationMatrix();
  Eigen::Map<Vec3>{residuals} = sqrt_information_ * (p + R * p_imu_antenna_ - p_enu_measured_);
  if (jacobians == nullptr) return true;
  using RowMajor3x4 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
  using RowMajor3x3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  if (jacobians[0] != nullptr) {
    Eigen::Map<RowMajor3x4>{jacobians[0]} = -sqrt_information_ * R *
                                            so3::Hat<double>(p_imu_antenna_) *
                                            QuaternionMinusJacobian(parameters[0]);
  }
  if (jacobians[1] != nullptr) Eigen::Map<RowMajor3x3>{jacobians[1]} = sqrt_information_;
  return true;
}

}  // namespace statebench::est
