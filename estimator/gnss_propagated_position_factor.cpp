#include "estimator/gnss_propagated_position_factor.hpp"

#include "core/so3.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/sqrt_information.hpp"

namespace statebench::est {
namespace {

Mat3 EffectiveCovariance(const Mat3& covariance_enu, const Vec3& p_imu_antenna,
                         const ImuPreintegration& pim, const Quat& q_world_imu_lin) {
  if (pim.empty()) return covariance_enu;
  const Mat3 R_i = q_world_imu_lin.normalized().toRotationMatrix();
  Eigen::Matrix<double, 3, 9> G = Eigen::Matrix<double, 3, 9>::Zero();
  G.block<3, 3>(0, kPreintRotation) = -R_i * pim.delta_R() * so3::Hat<double>(p_imu_antenna);
  G.block<3, 3>(0, kPreintPosition) = R_i;
  return covariance_enu + G * pim.covariance() * G.transpose();
}

}  // namespace

GnssPropagatedPositionFactor::GnssPropagatedPositionFactor(const Vec3& p_enu_measured,
                                                           const Mat3& covariance_enu,
                                                           const Vec3& p_imu_antenna,
                                                           ImuPreintegration propagation,
                                                           const Quat& q_world_imu_lin)
    : p_enu_measured_(p_enu_measured),
      p_imu_antenna_(p_imu_antenna),
      propagation_(std::move(propagation)),
      effective_covariance_(
          EffectiveCovariance(covariance_enu, p_imu_antenna, propagation_, q_world_imu_lin)),
      sqrt_information_(SqrtInformation<3>(effective_covariance_, "gnss propagated factor")) {}

bool GnssPropagatedPositionFactor::Evaluate(double const* const* parameters, double* residuals,
                                            double** jacobians) const {
  const Quat q_i = Eigen::Map<const Quat>(parameters[0]).normalized();
  const Eigen::Map<const Vec3> p_i(parameters[1]);
  const Eigen::Map<const Vec3> v_i(parameters[2]);
  const Eigen::Map<const Vec6> bias_i(parameters[3]);
  const ImuPreintegration& pim = propagation_;
  const double tau = pim.dt();
  const Vec3 dbg = bias_i.head<3>() - pim.bias_lin().gyro;
  const Vec3 dba = bias_i.tail<3>() - pim.bias_lin().accel;
  const Vec3 phi_bg = pim.d_R_d_bg() * dbg;
  const Mat3 dR_c = pim.delta_R() * so3::ExpMatrix<double>(phi_bg);
  const Vec3 dp_c = pim.delta_p() + pim.d_p_d_bg() * dbg + pim.d_p_d_ba() * dba;
  const Mat3 R_i = q_i.toRotationMatrix();

  // Antenna at t relative to p_i + v_i tau + g tau^2 / 2, in the IMU frame at i.
  const Vec3 lever_i = dp_c + dR_c * p_imu_antenna_;
  const Vec3 p_antenna = p_i + v_i * tau + 0.5 * kGravityWorld * tau * tau + R_i * lever_i;
  Eigen::Map<Vec3>{residuals} = sqrt_information_ * (p_antenna - p_enu_measured_);
  if (jacobians == nullptr) return true;

  using RowMajor3x3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
  using RowMajor3x4 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
  using RowMajor3x6 = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;
  if (jacobians[0] != nullptr) {
    Eigen::Map<RowMajor3x4>{jacobians[0]} = -sqrt_information_ * R_i * so3::Hat<double>(lever_i) *
                                            QuaternionMinusJacobian(parameters[0]);
  }
  if (jacobians[1] != nullptr) Eigen::Map<RowMajor3x3>{jacobians[1]} = sqrt_information_;
  if (jacobians[2] != nullptr) Eigen::Map<RowMajor3x3>{jacobians[2]} = sqrt_information_ * tau;
  if (jacobians[3] != nullptr) {
    RowMajor3x6 J;
    J.leftCols<3>() = R_i * (pim.d_p_d_bg() - dR_c * so3::Hat<double>(p_imu_antenna_) *
                                                  so3::RightJacobian(phi_bg) * pim.d_R_d_bg());
    J.rightCols<3>() = R_i * pim.d_p_d_ba();
    Eigen::Map<RowMajor3x6>{jacobians[3]} = sqrt_information_ * J;
  }
  return true;
}

}  // namespace statebench::est
