// Marginalisation prior on one navigation state and the window's global scalars (a GNSS
// receiver's time offset, bordered_chain.hpp): what MarginalizationPrior is for a state alone,
// on the joint tangent (dx, dg) with dg = g - g0 the globals' offsets from their values at the
// linearisation point:
//   r = r0 + J [dx; dg],  J^T J = H ((15 + G) x (15 + G)),  J^T r0 = gradient.
// Parameter blocks: q(4, RightQuaternionManifold), p(3), v(3), bias(6), then one block of size 1
// per global. Used only when the window has globals (without, MarginalizationPrior).
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Core>

#include "estimator/state_parameters.hpp"

namespace statebench::est {

class BorderedMarginalizationPrior final : public ceres::CostFunction {
 public:
  BorderedMarginalizationPrior(const StateParameters& x0, const Eigen::VectorXd& globals0,
                               const Eigen::MatrixXd& information,
                               const Eigen::VectorXd& gradient);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const StateParameters x0_;
  const Eigen::VectorXd globals0_;
  Eigen::MatrixXd J_;
  Eigen::VectorXd r0_;
};

}  // namespace statebench::est
