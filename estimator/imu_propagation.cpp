#include "estimator/imu_propagation.hpp"

#include "core/so3.hpp"
#include "estimator/mat3_blocks.hpp"

namespace statebench::est {

namespace {

// 3x3 block indices of the error state (core/state.hpp) and of the preintegration's (kPreint*).
constexpr int kRotationBlock = kRotationIndex / 3;
constexpr int kPositionBlock = kPositionIndex / 3;
constexpr int kVelocityBlock = kVelocityIndex / 3;
constexpr int kGyroBiasBlock = kGyroBiasIndex / 3;
constexpr int kAccelBiasBlock = kAccelBiasIndex / 3;

// F of the header comment, block by block.
Mat3Blocks<5, 5> TransitionBlocks(const NavState& state_i, const ImuPreintegration& pim) {
  const ImuBias bias{state_i.gyro_bias, state_i.accel_bias};
  const Mat3 R_i = state_i.q_world_imu.toRotationMatrix();
  const Mat3 dR = pim.CorrectedDeltaQ(bias).toRotationMatrix();
  const Vec3 dv = pim.CorrectedDeltaV(bias);
  const Vec3 dp = pim.CorrectedDeltaP(bias);

  Mat3Blocks<5, 5> F;
  for (int b = 0; b < 5; ++b) F.SetIdentity(b, b);
  F.SetGeneral(kRotationBlock, kRotationBlock, dR.transpose());
  F.SetGeneral(kRotationBlock, kGyroBiasBlock, pim.d_R_d_bg());
  F.SetGeneral(kPositionBlock, kRotationBlock, -R_i * so3::Hat(dp));
  F.SetScaledIdentity(kPositionBlock, kVelocityBlock, pim.dt());
  F.SetGeneral(kPositionBlock, kGyroBiasBlock, R_i * pim.d_p_d_bg());
  F.SetGeneral(kPositionBlock, kAccelBiasBlock, R_i * pim.d_p_d_ba());
  F.SetGeneral(kVelocityBlock, kRotationBlock, -R_i * so3::Hat(dv));
  F.SetGeneral(kVelocityBlock, kGyroBiasBlock, R_i * pim.d_v_d_bg());
  F.SetGeneral(kVelocityBlock, kAccelBiasBlock, R_i * pim.d_v_d_ba());
  return F;
}

// G (15x9) from the preintegration noise (rotation, velocity, position) to the state.
Mat3Blocks<5, 3> NoiseBlocks(const NavState& state_i) {
  const Mat3 R_i = state_i.q_world_imu.toRotationMatrix();
  Mat3Blocks<5, 3> G;
  G.SetIdentity(kRotationBlock, kPreintRotation / 3);
  G.SetGeneral(kVelocityBlock, kPreintVelocity / 3, R_i);
  G.SetGeneral(kPositionBlock, kPreintPosition / 3, R_i);
  return G;
}

}  // namespace

Mat15 PropagationJacobian(const NavState& state_i, const ImuPreintegration& pim) {
  return TransitionBlocks(state_i, pim).ToDense();
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
  Mat15 P = TransitionBlocks(state_i, pim).Congruence(covariance_i) +
            NoiseBlocks(state_i).Congruence(pim.covariance());
  const ImuNoise& n = pim.noise();
  P.block<3, 3>(kGyroBiasIndex, kGyroBiasIndex).diagonal().array() +=
      n.gyro_random_walk * n.gyro_random_walk * pim.dt();
  P.block<3, 3>(kAccelBiasIndex, kAccelBiasIndex).diagonal().array() +=
      n.accel_random_walk * n.accel_random_walk * pim.dt();
  out.covariance = P;  // exactly symmetric (Mat3Blocks::Congruence)
  return out;
}

PropagatedVelocity PropagateVelocity(const NavState& state_i, const Mat15& covariance_i,
                                     const ImuPreintegration& pim) {
  PropagatedVelocity out;
  if (pim.empty()) {
    out.state = state_i;
    out.velocity_covariance = covariance_i.block<3, 3>(kVelocityIndex, kVelocityIndex);
    return out;
  }
  out.state = pim.Predict(state_i);
  // Propagate's sum, block (v, v); the bias random walk does not reach it.
  out.velocity_covariance =
      TransitionBlocks(state_i, pim).CongruenceDiagonalBlock(covariance_i, kVelocityBlock) +
      NoiseBlocks(state_i).CongruenceDiagonalBlock(pim.covariance(), kVelocityBlock);
  return out;
}

}  // namespace statebench::est
