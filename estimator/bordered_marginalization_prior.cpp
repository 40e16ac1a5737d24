#include "estimator/bordered_marginalization_prior.hpp"

#include "estimator/marginalization_prior.hpp"

namespace statebench::est {

BorderedMarginalizationPrior::BorderedMarginalizationPrior(const StateParameters& x0,
                                                           const Eigen::VectorXd& globals0,
                                                           const Eigen::MatrixXd& information,
                                                           const Eigen::VectorXd& gradient)
    : x0_(x0), globals0_(globals0) {
  SqrtFactorOfInformation(information, gradient, &J_, &r0_);
  const int size = 15 + static_cast<int>(globals0.size());
  set_num_residuals(size);
  *mutable_parameter_block_sizes() = {4, 3, 3, 6};
  for (Eigen::Index i = 0; i < globals0.size(); ++i) mutable_parameter_block_sizes()->push_back(1);
}

bool BorderedMarginalizationPrior::Evaluate(double const* const* parameters, double* residuals,
                                            double** jacobians) const {
  const Eigen::Index num_globals = globals0_.size();
  Eigen::VectorXd delta(15 + num_globals);
  const Vec15 dx = StateDelta(x0_, parameters);
  delta.head<15>() = dx;
  for (Eigen::Index i = 0; i < num_globals; ++i) delta(15 + i) = parameters[4 + i][0] - globals0_(i);
  Eigen::Map<Eigen::VectorXd>(residuals, J_.rows()) = r0_ + J_ * delta;
  if (jacobians == nullptr) return true;
  StateBlockJacobians(J_.leftCols<15>(), dx, parameters[0], jacobians);
  for (Eigen::Index i = 0; i < num_globals; ++i) {
    if (jacobians[4 + i] != nullptr) {
      Eigen::Map<Eigen::VectorXd>(jacobians[4 + i], J_.rows()) = J_.col(15 + i);
    }
  }
  return true;
}

}  // namespace statebench::est
