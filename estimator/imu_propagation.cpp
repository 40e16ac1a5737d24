#include "estimator/imu_propagation.hpp"

#include "core/so3.hpp"

namespace statebench::est {

Mat15 PropagationJacobian(const NavState& state_i, const ImuPreintegration& pim) {
  const ImuBias bias{state_i.gyro_bias, state_i.accel_bias};
  const Mat3 R_i = state_i.q_world_imu.toRotationMatrix();
  const Mat3 dR = pim.CorrectedDeltaQ(bias).toRotationMatrix();
  const Vec3 dv = pim.CorrectedDeltaV(bias);
  const Vec3 dp = pim.CorrectedDeltaP(bias);
  const double dt = pim.dt();

  Mat15 F = Mat15::Identity();
  F.block<3, 3>(kRotationIndex, kRotationIndex) = dR.transpose();
  F.block<3, 3>(kRotationIndex, kGyroBiasIndex) = pim.d_R_d_bg();
  F.block<3, 3>(kPositionIndex, kRotationIndex) = -R_i * so3::Hat(dp);
  F.block<3, 3>(kPositionIndex, kVelocityIndex) = dt * Mat3::Identity();
  F.block<3, 3>(kPositionIndex, kGyroBiasIndex) = R_i * pim.d_p_d_bg();
  F.block<3, 3>(kPositionIndex, kAccelBiasIndex) = R_i * pim.d_p_d_ba();
  F.block<3, 3>(kVelocityIndex, kRotationIndex) = -R_i * so3::Hat(dv);
  F.block<3, 3>(kVelocityIndex, kGyroBiasIndex) = R_i * pim.d_v_d_bg();
  F.block<3, 3>(kVelocityIndex, kAccelBiasIndex) = R_i * pim.d_v_d_ba();
  return F;
}

PropagatedState Propagate(const NavState& state_i, const Mat15& covariance_i,
                          const ImuPreintegration& pim) {
  PropagatedState out;
  if (pim.empty()) {
    out.state = state_i;
    out.covariance = covariance_i;
    return out;
  }
  out.state = pim.Predict(state_i);
  const Mat15 F = PropagationJacobian(state_i, pim);
  const Mat3 R_i = state_i.q_world_imu.toRotationMatrix();
  // G (15x9) from the preintegration noise (rotation, velocity, position) to the state.
  Eigen::Matrix<double, 15, 9> G = Eigen::Matrix<double, 15, 9>::Zero();
  G.block<3, 3>(kRotationIndex, kPreintRotation) = Mat3::Identity();
  G.block<3, 3>(kVelocityIndex, kPreintVelocity) = R_i;
  G.block<3, 3>(kPositionIndex, kPreintPosition) = R_i;
  Mat15 P = F * covariance_i * F.transpose() + G * pim.covariance() * G.transpose();
  const ImuNoise& n = pim.noise();
  P.block<3, 3>(kGyroBiasIndex, kGyroBiasIndex).diagonal().array() +=
      n.gyro_random_walk * n.gyro_random_walk * pim.dt();
  P.block<3, 3>(kAccelBiasIndex, kAccelBiasIndex).diagonal().array() +=
      n.accel_random_walk * n.accel_random_walk * pim.dt();
  out.covariance = 0.5 * (P + P.transpose());
  return out;
}

}  // namespace statebench::est
