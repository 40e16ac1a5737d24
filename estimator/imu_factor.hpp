// Preintegrated IMU factor between states i and j (Forster et al., TRO 2017, eq. 45), with the
// first-order bias correction of eq. 44 around the preintegration's linearisation bias:
//   dR_c = dR Exp(J_R_bg dbg),  dv_c = dv + J_v_bg dbg + J_v_ba dba,  dp_c likewise,
//   r_R = Log(dR_c^T R_i^T R_j)
//   r_v = R_i^T (v_j - v_i - g dt) - dv_c
//   r_p = R_i^T (p_j - p_i - v_i dt - 1/2 g dt^2) - dp_c
// residual (r_R, r_v, r_p) whitened by the square-root information of the preintegrated
// covariance. The bias of state i is used; bias evolution is the BiasRandomWalkFactor's job.
//
// Parameter blocks (see StateParameters): q_i(4), p_i(3), v_i(3), bias_i(6), q_j(4), p_j(3),
// v_j(3). Rotations must use RightQuaternionManifold. Jacobians are analytic (right
// perturbations R Exp(d_phi), additive elsewhere):
//   dr_R/dphi_i = -Jr^-1(r_R) R_j^T R_i,   dr_R/dphi_j = Jr^-1(r_R),
//   dr_R/dbg    = -Jr^-1(r_R) Exp(r_R)^T Jr(J_R_bg dbg) J_R_bg,
//   dr_v/dphi_i = [R_i^T (v_j - v_i - g dt)]x,  dr_v/dv_i = -R_i^T,  dr_v/dv_j = R_i^T,
//   dr_p/dphi_i = [R_i^T (p_j - p_i - v_i dt - g dt^2/2)]x,  dr_p/dp_i = -R_i^T,
//   dr_p/dp_j = R_i^T,  dr_p/dv_i = -R_i^T dt,  dr_{v,p}/db = -J_{v,p}_b.
#pragma once

#include <ceres/sized_cost_function.h>

#include "core/eigen_types.hpp"
#include "core/state.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est {

class ImuFactor final : public ceres::SizedCostFunction<9, 4, 3, 3, 6, 4, 3, 3> {
 public:
  // Throws InputError if the preintegration is empty or its covariance is not invertible.
  explicit ImuFactor(ImuPreintegration preintegration);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // Unwhitened residual (r_R, r_v, r_p) between two states, bias taken from state_i.
  Vec9 Residual(const NavState& state_i, const NavState& state_j) const;

  const ImuPreintegration& preintegration() const { return preintegration_; }
  const Mat9& sqrt_information() const { return sqrt_information_; }

 private:
  const ImuPreintegration preintegration_;
  const Mat9 sqrt_information_;
};

}  // namespace statebench::est
