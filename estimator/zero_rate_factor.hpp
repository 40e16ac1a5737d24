// Zero angular rate at a standstill (a "ZARU"): while the vehicle stands still the gyro measures
// its own bias (the Earth's rotation, 7.3e-5 rad/s at most, is below the noise of the MEMS
// gyros this serves and is neglected, as the flat non-rotating world of core/state.hpp does).
// The mean of the raw gyro samples over a still span [t1, t2] is a direct measurement of the
// gyro bias of the state the span belongs to (3 residuals):
//   r = S (b_g - mean(gyro)),   S = I / sigma,   sigma = gyro_noise_density / sqrt(t2 - t1)
// (the white noise averaged over the span). Parameter block: bias(6) of the state, ordered
// (gyro, accel). Linear, analytic Jacobian.
#pragma once

#include <ceres/sized_cost_function.h>

#include "core/eigen_types.hpp"

namespace statebench::est {

class ZeroRateFactor final : public ceres::SizedCostFunction<3, 6> {
 public:
  // Throws InputError unless the mean is finite and sigma_radps > 0.
  ZeroRateFactor(const Vec3& mean_gyro_radps, double sigma_radps);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Vec3 mean_gyro_;
  double sqrt_info_;
};

}  // namespace statebench::est
