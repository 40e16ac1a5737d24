// GNSS antenna position factor for a fix taken between two states, placed at its own stamp.
//
// Design: the fix at t is attached to the latest state i with t_i <= t and the state is carried
// to t with the IMU preintegrated over [t_i, t] (ImuPreintegration::FromSamples, which
// interpolates the sample at t), bias-corrected to first order with the bias of state i:
//   R_t = R_i dR_c,   p_t = p_i + v_i tau + 1/2 g tau^2 + R_i dp_c,   tau = t - t_i
//   r   = S (p_t + R_t p_imu_antenna - p_enu_measured)
// Why one-sided propagation and not interpolation between i and j:
//  - it is exact under the same motion model as the IMU factor (linear interpolation of p
//    between states misses a tau (dt - tau) / 2 term: 2.5 cm at 2 m/s^2 between keyframes
//    0.1 s apart), and needs no extrapolation of rotation;
//  - it touches the blocks of one state only (q, p, v, bias of i), so the graph stays as sparse
//    as with a unary factor at the closest state.
// The uncertainty of the partial delta is added to the fix covariance,
//   Cov = Cov_fix + G Cov_pre G^T,  G = d(antenna position)/d(phi, v, p of the delta)
//       = [-R_i dR [p_imu_antenna]x, 0, R_i],
// evaluated once at the orientation given at construction (tiny: 1e-6 m over 10 ms). Its
// correlation with the IMU factor i -> j, which integrates the same samples, is neglected.
// With tau = 0 this is GnssPositionFactor plus unused v and bias blocks.
//
// Parameter blocks: q_i(4, RightQuaternionManifold), p_i(3), v_i(3), bias_i(6). Analytic
// Jacobians:
//   dr/dphi_i = -S R_i [dp_c + dR_c l]x,  dr/dp_i = S,  dr/dv_i = S tau,
//   dr/dbg = S R_i (J_p_bg - dR_c [l]x Jr(J_R_bg dbg) J_R_bg),  dr/dba = S R_i J_p_ba.
#pragma once

#include <ceres/sized_cost_function.h>

#include "core/eigen_types.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est {

class GnssPropagatedPositionFactor final : public ceres::SizedCostFunction<3, 4, 3, 3, 6> {
 public:
  // propagation covers [t_i, t_fix] (it may have zero steps when the fix is at t_i);
  // q_world_imu_lin is the current estimate of R_i, used only for the covariance.
  // Throws InputError if the resulting covariance is not positive definite.
  GnssPropagatedPositionFactor(const Vec3& p_enu_measured, const Mat3& covariance_enu,
                               const Vec3& p_imu_antenna, ImuPreintegration propagation,
                               const Quat& q_world_imu_lin);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // The fix covariance with the propagation uncertainty added.
  const Mat3& effective_covariance() const { return effective_covariance_; }
  const Mat3& sqrt_information() const { return sqrt_information_; }
  const ImuPreintegration& propagation() const { return propagation_; }

 private:
  const Vec3 p_enu_measured_;
  const Vec3 p_imu_antenna_;
  const ImuPreintegration propagation_;
  const Mat3 effective_covariance_;
  const Mat3 sqrt_information_;
};

}  // namespace statebench::est
