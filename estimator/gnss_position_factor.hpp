// GNSS antenna position factor at a state (unary):
//   r = S (p_world_imu + R_world_imu p_imu_antenna - p_enu_measured)
// with S the square-root information of the fix's ENU covariance. The lever arm is applied
// through the current orientation estimate, so a fix also informs the attitude. (The paper
// moves the fix to the IMU once with a fixed rotation; this keeps the coupling in the graph.)
// Parameter blocks: q_world_imu(4, RightQuaternionManifold), p_world(3). Analytic Jacobians:
//   dr/dphi = -S R [p_imu_antenna]x,   dr/dp = S.
#pragma once

#include <ceres/sized_cost_function.h>

#include "core/eigen_types.hpp"

namespace statebench::est {

class GnssPositionFactor final : public ceres::SizedCostFunction<3, 4, 3> {
 public:
  // Throws InputError if the covariance is not finite and positive definite.
  GnssPositionFactor(const Vec3& p_enu_measured, const Mat3& covariance_enu,
                     const Vec3& p_imu_antenna);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const Vec3 p_enu_measured_;
  const Vec3 p_imu_antenna_;
  const Mat3 sqrt_information_;
};

}  // namespace statebench::est
