// Random-walk prior between the bias blocks of consecutive states i and j (6 residuals):
//   r = S (b_j - b_i),  S = diag(1 / (rw_g sqrt(dt)) I3, 1 / (rw_a sqrt(dt)) I3)
// the Kalibr discretisation of a bias random walk over dt = t_j - t_i (variance rw^2 dt).
// Parameter blocks: bias_i(6), bias_j(6), ordered (gyro, accel). Linear, analytic Jacobians.
#pragma once

#include <ceres/sized_cost_function.h>

#include "core/eigen_types.hpp"
#include "estimator/imu_noise.hpp"

namespace statebench::est {

class BiasRandomWalkFactor final : public ceres::SizedCostFunction<6, 6, 6> {
 public:
  // Throws InputError unless dt_s > 0 and the noise is valid.
  BiasRandomWalkFactor(const ImuNoise& noise, double dt_s);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const Vec6& sqrt_information_diagonal() const { return sqrt_info_; }

 private:
  Vec6 sqrt_info_;
};

}  // namespace statebench::est
