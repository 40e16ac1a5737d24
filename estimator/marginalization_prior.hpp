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

#include "core/eigen_types.hpp"
#include "estimator/state_parameters.hpp"

namespace statebench::est {

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
