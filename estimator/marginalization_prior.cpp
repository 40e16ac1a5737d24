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
  const Eigen::SelfAdjointEigenSolver<Mat15> eig(0.5 * (information + information.transpose()));
  const double threshold = 1e-12 * std::max(eig.eigenvalues().maxCoeff(), 0.0);
  Vec15 sqrt_l = Vec15::Zero(), inv_sqrt_l = Vec15::Zero();
  for (int i = 0; i < 15; ++i) {
    const double l = eig.eigenvalues()(i);
    if (l > threshold) {
      sqrt_l(i) = std::sqrt(l);
      inv_sqrt_l(i) = 1.0 / sqrt_l(i);
    }
  }
  J_ = sqrt_l.asDiagonal() * eig.eigenvectors().transpose();
  r0_ = inv_sqrt_l.asDiagonal() * eig.eigenvectors().transpose() * gradient;
}

MarginalizationPrior* MarginalizationPrior::FromCovariance(const NavState& mean,
                                                           const Mat15& covariance) {
  const Mat15 S = SqrtInformation<15>(covariance, "state prior");
  return new MarginalizationPrior(StateParameters::FromNavState(mean), S.transpose() * S,
                                  Vec15::Zero());
}

Vec15 MarginalizationPrior::Delta(double const* const* parameters) const {
  const Eigen::Map<const Quat> q(parameters[0]);
  const Eigen::Map<const Quat> q0(x0_.q_world_imu.data());
  Vec15 dx;
  dx.segment<3>(kRotationIndex) = so3::Log<double>(q0.conjugate() * q.normalized());
  dx.segment<3>(kPositionIndex) =
      Eigen::Map<const Vec3>(parameters[1]) - Eigen::Map<const Vec3>(x0_.p_world.data());
  dx.segment<3>(kVelocityIndex) =
      Eigen::Map<const Vec3>(parameters[2]) - Eigen::Map<const Vec3>(x0_.v_world.data());
  dx.segment<6>(kGyroBiasIndex) =
      Eigen::Map<const Vec6>(parameters[3]) - Eigen::Map<const Vec6>(x0_.bias.data());
  return dx;
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
