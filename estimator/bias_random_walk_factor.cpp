#include "estimator/bias_random_walk_factor.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace statebench::est {

BiasRandomWalkFactor::BiasRandomWalkFactor(const ImuNoise& noise, double dt_s) {
  std::string why;
  if (!noise.IsValid(&why)) throw InputError("bias random walk factor: " + why);
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) {
    throw InputError("bias random walk factor: dt must be positive, got " + std::to_string(dt_s));
  }
  const double sqrt_dt = std::sqrt(dt_s);
  sqrt_info_.head<3>().setConstant(1.0 / (noise.gyro_random_walk * sqrt_dt));
  sqrt_info_.tail<3>().setConstant(1.0 / (noise.accel_random_walk * sqrt_dt));
}

bool BiasRandomWalkFactor::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  const Eigen::Map<const Vec6> b_i(parameters[0]);
  const Eigen::Map<const Vec6> b_j(parameters[1]);
  Eigen::Map<Vec6>{residuals} = sqrt_info_.cwiseProduct(b_j - b_i);
  using RowMajor6 = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    Eigen::Map<RowMajor6>{jacobians[0]} = -sqrt_info_.asDiagonal().toDenseMatrix();
  }
  if (jacobians != nullptr && jacobians[1] != nullptr) {
    Eigen::Map<RowMajor6>{jacobians[1]} = sqrt_info_.asDiagonal().toDenseMatrix();
  }
  return true;
}

}  // namespace statebench::est
