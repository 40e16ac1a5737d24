#include "estimator/marginalization_prior.hpp"

#include <Eigen/Eigenvalues>

#include "core/so3.hpp"
#include "core/state.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/sqrt_information.hpp"

namespace statebench::est {

MarginalizationPrior::MarginalizationPrior(const StateParameters& x0, const Mat15& information,
                                           const Vec15& gradient)
    : x0_(x0) {
  SqrtFactorOfInformation(information, gradient, &J_, &r0_);
}

MarginalizationPrior* MarginalizationPrior::FromCovariance(const NavState& mean,
                                                           const Mat15& covariance) {
  const Mat15 S = SqrtInformation<15>(covariance, "state prior");
  return new MarginalizationPrior(StateParameters::FromNavState(mean), S.transpose() * S,
                                  Vec15::Zero());
}

Vec15 StateDelta(const StateParameters& x0, double const* const* parameters) {
  const Eigen::Map<const Quat> q(parameters[0]);
  const Eigen::Map<const Quat> q0(x0.q_world_imu.data());
  Vec15 dx;
  dx.segment<3>(kRotationIndex) = so3::Log<double>(q0.conjugate() * q.normalized());
  dx.segment<3>(kPositionIndex) =
      Eigen::Map<const Vec3>(parameters[1]) - Eigen::Map<const Vec3>(x0.p_world.data());
  dx.segment<3>(kVelocityIndex) =
      Eigen::Map<const Vec3>(parameters[2]) - Eigen::Map<const Vec3>(x0.v_world.data());
  dx.segment<6>(kGyroBiasIndex) =
      Eigen::Map<const Vec6>(parameters[3]) - Eigen::Map<const Vec6>(x0.bias.data());
  return dx;
}

void StateBlockJacobians(const Eigen::Ref<const Eigen::MatrixXd>& J_state, const Vec15& dx,
                         const double* q, double** jacobians) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Index rows = J_state.rows();
  if (jacobians[0] != nullptr) {
    const Mat3 jr_inv = so3::RightJacobianInverse(dx.segment<3>(kRotationIndex));
    Eigen::Map<RowMajor>(jacobians[0], rows, 4) =
        J_state.middleCols<3>(kRotationIndex) * jr_inv * QuaternionMinusJacobian(q);
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<RowMajor>(jacobians[1], rows, 3) = J_state.middleCols<3>(kPositionIndex);
  }
  if (jacobians[2] != nullptr) {
    Eigen::Map<RowMajor>(jacobians[2], rows, 3) = J_state.middleCols<3>(kVelocityIndex);
  }
  if (jacobians[3] != nullptr) {
    Eigen::Map<RowMajor>(jacobians[3], rows, 6) = J_state.middleCols<6>(kGyroBiasIndex);
  }
}

Vec15 MarginalizationPrior::Delta(double const* const* parameters) const {
  return StateDelta(x0_, parameters);
}

bool MarginalizationPrior::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  const Vec15 dx = Delta(parameters);
  Eigen::Map<Vec15>{residuals} = r0_ + J_ * dx;
  if (jacobians == nullptr) return true;
  using RowMajor15x3 = Eigen::Matrix<double, 15, 3, Eigen::RowMajor>;
  using RowMajor15x4 = Eigen::Matrix<double, 15, 4, Eigen::RowMajor>;
  using RowMajor15x6 = Eigen::Matrix<double, 15, 6, Eigen::RowMajor>;
  if (jacobians[0] != nullptr) {
    const Mat3 jr_inv = so3::RightJacobianInverse(dx.segment<3>(kRotationIndex));
    Eigen::Map<RowMajor15x4>{jacobians[0]} =
        J_.middleCols<3>(kRotationIndex) * jr_inv * QuaternionMinusJacobian(parameters[0]);
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<RowMajor15x3>{jacobians[1]} = J_.middleCols<3>(kPositionIndex);
  }
  if (jacobians[2] != nullptr) {
    Eigen::Map<RowMajor15x3>{jacobians[2]} = J_.middleCols<3>(kVelocityIndex);
  }
  if (jacobians[3] != nullptr) {
    Eigen::Map<RowMajor15x6>{jacobians[3]} = J_.middleCols<6>(kGyroBiasIndex);
  }
  return true;
}

}  // namespace statebench::est
