#include "estimator/zero_rate_factor.hpp"

#include <cmath>

#include "core/error.hpp"

namespace statebench::est {

ZeroRateFactor::ZeroRateFactor(const Vec3& mean_gyro_radps, double sigma_radps)
    : mean_gyro_(mean_gyro_radps), sqrt_info_(1.0 / sigma_radps) {
  if (!mean_gyro_radps.allFinite() || !(sigma_radps > 0.0) || !std::isfinite(sqrt_info_)) {
    throw InputError("zero-rate factor: non-finite mean or sigma not positive");
  }
}

bool ZeroRateFactor::Evaluate(double const* const* parameters, double* residuals,
                              double** jacobians) const {
  const Eigen::Map<const Vec3> b_g(parameters[0]);
  Eigen::Map<Vec3>{residuals} = sqrt_info_ * (b_g - mean_gyro_);
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J(jacobians[0]);
    J.setZero();
    J.leftCols<3>().diagonal().setConstant(sqrt_info_);
  }
  return true;
}

}  // namespace statebench::est
