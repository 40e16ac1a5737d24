#include "estimator/gnss_error_state_factor.hpp"

#include "core/error.hpp"

namespace statebench::est {

GnssErrorStateFactor::GnssErrorStateFactor(std::unique_ptr<ceres::CostFunction> base,
                                           const Mat3& sqrt_information)
    : base_(std::move(base)), sqrt_information_(sqrt_information) {
  if (base_ == nullptr || base_->num_residuals() != 3) {
    throw InputError("gnss error state: the wrapped factor must have three residuals");
  }
  set_num_residuals(3);
  *mutable_parameter_block_sizes() = base_->parameter_block_sizes();
  num_base_blocks_ = static_cast<int>(base_->parameter_block_sizes().size());
  for (int k = 0; k < 3; ++k) mutable_parameter_block_sizes()->push_back(1);
}

bool GnssErrorStateFactor::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  if (!base_->Evaluate(parameters, residuals, jacobians)) return false;
  const Vec3 e(parameters[num_base_blocks_][0], parameters[num_base_blocks_ + 1][0],
               parameters[num_base_blocks_ + 2][0]);
  Eigen::Map<Vec3>{residuals} += sqrt_information_ * e;
  if (jacobians == nullptr) return true;
  for (int k = 0; k < 3; ++k) {
    if (double* J = jacobians[num_base_blocks_ + k]) {
      Eigen::Map<Vec3>{J} = sqrt_information_.col(k);
    }
  }
  return true;
}

}  // namespace statebench::est
