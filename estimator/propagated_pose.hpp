// The navigation state at a stamp between states, as a function of the parameter blocks of the
// latest state i at or before it: the one-sided IMU propagation of GnssPropagatedPositionFactor,
// templated so automatic differentiation gives the factors' Jacobians.
//
//   R_t = R_i dR(bg),  v_t = v_i + g tau + R_i dv(b),  p_t = p_i + v_i tau + 1/2 g tau^2 + R_i dp(b)
// with the deltas over [t_i, t] corrected to first order for the state's bias (Forster eq. 44):
//   dR(bg) = dR Exp(J_R_bg (bg - bg_lin)), dv(b) = dv + J_v_bg dbg + J_v_ba dba, same for dp.
#pragma once

#include "core/eigen_types.hpp"
#include "core/so3.hpp"
#include "core/state.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est {

// The constants of one preintegrated interval the propagation needs.
struct PropagationDeltas {
  double tau_s = 0.0;
  Quat dq = Quat::Identity();
  Vec3 dv = Vec3::Zero();
  Vec3 dp = Vec3::Zero();
  Mat3 J_R_bg = Mat3::Zero();
  Mat3 J_v_bg = Mat3::Zero();
  Mat3 J_v_ba = Mat3::Zero();
  Mat3 J_p_bg = Mat3::Zero();
  Mat3 J_p_ba = Mat3::Zero();
  Vec3 bg_lin = Vec3::Zero();
  Vec3 ba_lin = Vec3::Zero();

  static PropagationDeltas From(const ImuPreintegration& p) {
    PropagationDeltas d;
    d.tau_s = p.dt();
    d.dq = p.delta_q();
    d.dv = p.delta_v();
    d.dp = p.delta_p();
    d.J_R_bg = p.d_R_d_bg();
    d.J_v_bg = p.d_v_d_bg();
    d.J_v_ba = p.d_v_d_ba();
    d.J_p_bg = p.d_p_d_bg();
    d.J_p_ba = p.d_p_d_ba();
    d.bg_lin = p.bias_lin().gyro;
    d.ba_lin = p.bias_lin().accel;
    return d;
  }
};

template <typename T>
struct PropagatedPose {
  Eigen::Quaternion<T> q_world_imu;
  Eigen::Matrix<T, 3, 1> p_world;
  Eigen::Matrix<T, 3, 1> v_world;
};

// q: 4 coefficients (x, y, z, w); p, v: 3; bias: 6 (gyro, accel). See state_parameters.hpp.
template <typename T>
PropagatedPose<T> Propagate(const PropagationDeltas& d, const T* q, const T* p, const T* v,
                            const T* bias) {
  using V3 = Eigen::Matrix<T, 3, 1>;
  const Eigen::Map<const Eigen::Quaternion<T>> q_i(q);
  const Eigen::Map<const V3> p_i(p);
  const Eigen::Map<const V3> v_i(v);
  const V3 dbg = Eigen::Map<const V3>(bias) - d.bg_lin.cast<T>();
  const V3 dba = Eigen::Map<const V3>(bias + 3) - d.ba_lin.cast<T>();
  const V3 phi = d.J_R_bg.cast<T>() * dbg;
  const Eigen::Quaternion<T> dq = d.dq.cast<T>() * so3::Exp<T>(phi);
  const V3 dv = d.dv.cast<T>() + d.J_v_bg.cast<T>() * dbg + d.J_v_ba.cast<T>() * dba;
  const V3 dp = d.dp.cast<T>() + d.J_p_bg.cast<T>() * dbg + d.J_p_ba.cast<T>() * dba;
  const T tau(d.tau_s);
  const V3 g = kGravityWorld.cast<T>();
  PropagatedPose<T> out;
  out.q_world_imu = q_i * dq;
  out.v_world = v_i + g * tau + q_i * dv;
  out.p_world = p_i + v_i * tau + T(0.5) * g * tau * tau + q_i * dp;
  return out;
}

}  // namespace statebench::est
