#include "estimator/ekf_output_mapping.hpp"

#include "core/so3.hpp"

namespace statebench::est::ekf {

StateEstimate EkfOutput(const Snapshot& snap, TimeNs t_out_ns, const EkfOutputContext& c) {
  VecN s = snap.x;
  const double dt = ToSeconds(t_out_ns - snap.t_ns);
  if (dt > 0.0) {
    s += dt * c.model.Derivative(s, snap.accel_x, snap.steering);
    s[kPsi] = so3::WrapAngle(s[kPsi]);
  }
  const Mat3 R_world_body = YawRotation(s[kPsi]);
  const Mat3 R_world_imu = R_world_body * c.R_body_imu;
  const Vec3 omega_body(0.0, 0.0, s[kR]);
  const Vec3 v_body = Vec3(s[kVx], s[kVy], 0.0) + omega_body.cross(c.p_body_imu);
  StateEstimate out;
  NavState& n = out.state;
  n.t_ns = t_out_ns;
  n.q_world_imu = Quat(R_world_imu).normalized();
  const Vec3 lever_world = R_world_body * c.p_body_imu;
  n.p_world = Vec3(s[kX], s[kY], snap.z) + lever_world;
  n.v_world = R_world_body * v_body;
  const Mat3 R_imu_body = c.R_body_imu.transpose();
  n.gyro_bias = R_imu_body * Vec3(0.0, 0.0, s[kBg]);
  n.accel_bias = R_imu_body * Vec3(s[kBa], 0.0, 0.0);

  // Error vector e (16): [8 filter states, z, roll_w, pitch_w, vz, bg_x, bg_y, ba_y, ba_z]
  // (small world-frame tilts, body-frame bias components), mapped to the 15x15 ordering.
  constexpr int kE = 16;
  Eigen::Matrix<double, kE, 1> variances;
  const double rp = c.options.roll_pitch_sigma_rad * c.options.roll_pitch_sigma_rad;
  const double vz = c.options.vertical_velocity_sigma_mps * c.options.vertical_velocity_sigma_mps;
  const double bg = c.options.init_gyro_bias_sigma_radps * c.options.init_gyro_bias_sigma_radps;
  const double ba = c.options.init_accel_bias_sigma_mps2 * c.options.init_accel_bias_sigma_mps2;
  variances << VecN::Zero(), snap.Pz, rp, rp, vz, bg, bg, ba, ba;
  Eigen::Matrix<double, kE, kE> C = variances.asDiagonal();
  C.topLeftCorner<kN, kN>() = snap.P;
  Eigen::Matrix<double, 15, kE> J = Eigen::Matrix<double, 15, kE>::Zero();
  // World tilt columns (roll_w, pitch_w, psi) for rotation, position and velocity.
  const int tilt[3] = {9, 10, kPsi};
  const Mat3 R_imu_world = R_world_imu.transpose();
  const Mat3 dpos_dtilt = -so3::Hat<double>(lever_world);
  const Mat3 dvel_dtilt = -so3::Hat<double>(n.v_world);
  for (int i = 0; i < 3; ++i) {
    J.block<3, 1>(kRotationIndex, tilt[i]) = R_imu_world.col(i);
    J.block<3, 1>(kPositionIndex, tilt[i]) = dpos_dtilt.col(i);
    J.block<3, 1>(kVelocityIndex, tilt[i]) = dvel_dtilt.col(i);
  }
  J(kPositionIndex + 0, kX) = 1.0;
  J(kPositionIndex + 1, kY) = 1.0;
  J(kPositionIndex + 2, 8) = 1.0;
  J.block<3, 1>(kVelocityIndex, kVx) = R_world_body.col(0);
  J.block<3, 1>(kVelocityIndex, kVy) = R_world_body.col(1);
  J.block<3, 1>(kVelocityIndex, kR) = R_world_body * Vec3::UnitZ().cross(c.p_body_imu);
  J(kVelocityIndex + 2, 11) = 1.0;
  J.block<3, 1>(kGyroBiasIndex, 12) = R_imu_body.col(0);
  J.block<3, 1>(kGyroBiasIndex, 13) = R_imu_body.col(1);
  J.block<3, 1>(kGyroBiasIndex, kBg) = R_imu_body.col(2);
  J.block<3, 1>(kAccelBiasIndex, kBa) = R_imu_body.col(0);
  J.block<3, 1>(kAccelBiasIndex, 14) = R_imu_body.col(1);
  J.block<3, 1>(kAccelBiasIndex, 15) = R_imu_body.col(2);
  const Mat15 cov = J * C * J.transpose();
  out.covariance = 0.5 * (cov + cov.transpose());
  if (c.frame != nullptr) {
    const GeodeticPoint g = c.frame->ToGeodetic(n.p_world);
    out.latitude_deg = g.latitude_deg;
    out.longitude_deg = g.longitude_deg;
    out.altitude_m = g.altitude_m;
  }
  return out;
}

}  // namespace statebench::est::ekf
