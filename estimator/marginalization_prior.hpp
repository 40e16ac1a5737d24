// Prior on one navigation state left by marginalisation (or given at initialisation).
//
// The information H (15x15) and gradient g the eliminated states carried are fixed at the
// linearisation point x0, the state's estimate when its predecessor left the window. Only the
// prior is fixed there: the state's other factors (IMU, GNSS, lidar) are relinearised at every
// solve, so two linearisation points of one state meet in the window. This is not
// first-estimate Jacobians (Huang et al.): in directions the measurements leave unobservable
// (position and yaw without GNSS) the mismatch can create information the data do not hold,
// making the covariance over-confident there; with GNSS every direction is observed and the
// effect is second order. Not measured separately (issue 11 lists it).
// The prior's residual is linear in the tangent offset from x0:
//   dx = x [-] x0 = (Log(R0^T R), p - p0, v - v0, b - b0)      (core/state.hpp ordering)
//   r  = r0 + J dx,  with J^T J = H and J^T r0 = g,
// so 1/2 |r|^2 = 1/2 dx^T H dx + g^T dx + const. From H = V diag(l) V^T:
//   J = diag(sqrt(l)) V^T,  r0 = diag(1/sqrt(l)) V^T g   (rows with l ~ 0 are zero).
// Parameter blocks: q(4, RightQuaternionManifold), p(3), v(3), bias(6). The Jacobian w.r.t.
// the rotation is J_rot Jr^-1(Log(R0^T R)), exact for the Minus above.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "core/eigen_types.hpp"
#include "estimator/state_parameters.hpp"

namespace statebench::est {

// J and r0 with J^T J = H and J^T r0 = g from H = V diag(l) V^T (rows with l below 1e-12 of the
// largest are zero): J = diag(sqrt(l)) V^T, r0 = diag(1/sqrt(l)) V^T g.
template <typename Matrix, typename Vector>
void SqrtFactorOfInformation(const Matrix& information, const Vector& gradient, Matrix* J,
                             Vector* r0) {
  const Eigen::SelfAdjointEigenSolver<Matrix> eig(0.5 * (information + information.transpose()));
  const double threshold = 1e-12 * std::max(eig.eigenvalues().maxCoeff(), 0.0);
  Vector sqrt_l = Vector::Zero(gradient.size()), inv_sqrt_l = Vector::Zero(gradient.size());
  for (Eigen::Index i = 0; i < gradient.size(); ++i) {
    const double l = eig.eigenvalues()(i);
    if (l > threshold) {
      sqrt_l(i) = std::sqrt(l);
      inv_sqrt_l(i) = 1.0 / sqrt_l(i);
    }
  }
  *J = sqrt_l.asDiagonal() * eig.eigenvectors().transpose();
  *r0 = inv_sqrt_l.asDiagonal() * eig.eigenvectors().transpose() * gradient;
}

// dx = x [-] x0 for a state's four blocks (q, p, v, bias), core/state.hpp ordering.
Vec15 StateDelta(const StateParameters& x0, double const* const* parameters);

// The prior's residual rows' Jacobians w.r.t. the state's four blocks (ambient, row-major into
// jacobians[0..3], each skipped when null) from its tangent Jacobian J_state (rows x 15) at
// dx = StateDelta(...).
void StateBlockJacobians(const Eigen::Ref<const Eigen::MatrixXd>& J_state, const Vec15& dx,
                         const double* q, double** jacobians);

class MarginalizationPrior final : public ceres::SizedCostFunction<15, 4, 3, 3, 6> {
 public:
  MarginalizationPrior(const StateParameters& x0, const Mat15& information, const Vec15& gradient);

  // Prior N(mean, covariance) on a state: H = covariance^-1, g = 0 at x0 = mean.
  // Throws InputError if the covariance is not positive definite.
  static MarginalizationPrior* FromCovariance(const NavState& mean, const Mat15& covariance);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // dx = x [-] x0 for the four blocks.
  Vec15 Delta(double const* const* parameters) const;

 private:
  const StateParameters x0_;
  Mat15 J_;
  Vec15 r0_;
};

}  // namespace statebench::est
