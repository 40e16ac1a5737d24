// Mean and covariance of a navigation state carried forward through a preintegrated IMU
// interval: the IMU-rate output between smoother updates, and the prediction the gates use.
//
// Mean: ImuPreintegration::Predict (biases held). Covariance, error state in core/state.hpp
// ordering (rotation as a right perturbation, position and velocity in the world frame):
//   P_j = F P_i F^T + G Q_pre G^T + Q_bias
// From R_j = R_i dR,  v_j = v_i + g dt + R_i dv,  p_j = p_i + v_i dt + 1/2 g dt^2 + R_i dp and
// the first-order bias corrections of the deltas (J_* = ImuPreintegration bias Jacobians):
//   dtheta_j = dR^T dtheta_i + J_R_bg dbg
//   dp_j     = dp_i + dt dv_i - R_i [dp]x dtheta_i + R_i (J_p_bg dbg + J_p_ba dba)
//   dv_j     = dv_i - R_i [dv]x dtheta_i + R_i (J_v_bg dbg + J_v_ba dba)
//   db_j     = db_i
// G maps the preintegration noise (rotation, velocity, position; kPreint*) into the state:
// identity on rotation, R_i on velocity and position. Q_bias is the random walk over dt,
// diag(rw_g^2 dt I3, rw_a^2 dt I3). The Jacobians are exact at the preintegration's
// linearisation bias, which should be the state's bias.
#pragma once

#include "core/eigen_types.hpp"
#include "core/state.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est {

struct PropagatedState {
  NavState state;
  Mat15 covariance = Mat15::Zero();
};

// Transition matrix F of the error state over the interval (see the header comment).
Mat15 PropagationJacobian(const NavState& state_i, const ImuPreintegration& preintegration);

PropagatedState Propagate(const NavState& state_i, const Mat15& covariance_i,
                          const ImuPreintegration& preintegration);

// Propagate's mean and the velocity block of its covariance alone, the same bits: for the tests
// that read no other block (the standstill test), a fifth of the covariance's arithmetic.
struct PropagatedVelocity {
  NavState state;
  Mat3 velocity_covariance = Mat3::Zero();
};
PropagatedVelocity PropagateVelocity(const NavState& state_i, const Mat15& covariance_i,
                                     const ImuPreintegration& preintegration);

}  // namespace statebench::est
