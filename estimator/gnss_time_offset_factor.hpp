// GNSS antenna position factor with the receiver's time offset as a parameter.
//
// Sign: the offset d is how late the receiver's stamps are against the IMU clock: the fix
// stamped t was taken at t - d (d > 0 for a receiver whose stamps lag). The antenna at t - d is,
// to first order in d,
//   p_ant(t - d) ~= p_ant(t) - d v_ant(t),   v_ant(t) = v_t + R_t (omega_t x l),
// with p_ant(t) the prediction of GnssPropagatedPositionFactor (the anchor state i carried to the
// stamp with the IMU) and the antenna's velocity at t from the same propagation:
//   v_t = v_i + g tau + R_i dv,   R_t = R_i dR,   omega_t = raw gyro at t - gyro bias (lin.).
// The velocity term uses the preintegrated deltas at the propagation's linearisation bias (its
// bias dependence, d * tau * dbias, is left out of the model: under 1e-4 m for d = 0.1 s, tau =
// 0.1 s and a bias error of 0.01 m/s^2). The first-order shift errs by 1/2 a d^2: 1 cm at
// 2 m/s^2 and d = 0.1 s, inside a fix's noise.
//   r = S (p_ant(t) - d v_ant(t) - p_measured)
// Parameter blocks: q_i(4), p_i(3), v_i(3), bias_i(6), d(1). Jacobians: those of the propagated
// factor plus
//   dr/dphi_i += d S R_i [a]x,  a = dv + dR (omega_t x l),    dr/dv_i += -d S,
//   dr/dd = -S v_ant(t).
#pragma once

#include <ceres/sized_cost_function.h>

#include "estimator/gnss_propagated_position_factor.hpp"

namespace statebench::est {

class GnssTimeOffsetFactor final : public ceres::SizedCostFunction<3, 4, 3, 3, 6, 1> {
 public:
  // omega_raw_imu: the raw gyro at the fix's stamp. Throws as GnssPropagatedPositionFactor.
  GnssTimeOffsetFactor(const Vec3& p_enu_measured, const Mat3& covariance_enu,
                       const Vec3& p_imu_antenna, ImuPreintegration propagation,
                       const Quat& q_world_imu_lin, const Vec3& omega_raw_imu);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const Mat3& sqrt_information() const { return position_.sqrt_information(); }

 private:
  const GnssPropagatedPositionFactor position_;
  const Vec3 lever_velocity_i_;  // a = dv + dR (omega_t x l), in the IMU frame at i
};

}  // namespace statebench::est
