// Velocity of a point of the vehicle at a stamp between states, in a frame fixed to the vehicle
// or in the world frame: the speed encoder / body-velocity odometry, the non-holonomic
// constraint (zero lateral and vertical velocity at the rear axle) and the zero-velocity factor
// measure it in a vehicle frame; a GNSS receiver's Doppler velocity of its antenna in ENU.
//
// The state at the stamp comes from the latest state at or before it through the IMU
// (propagated_pose.hpp). The point c sits at p_imu_point in the IMU frame and the measurement
// frame has rotation R_imu_frame:
//   v_c = R_imu_frame^T ( R_t^T v_t + (w_meas - b_g) x p_imu_point )
//   r   = S (v_c - v_measured)
// or, in the world frame (GNSS velocity: antenna velocity = v + R (omega x lever arm)),
//   v_c = R_t ( R_t^T v_t + (w_meas - b_g) x p_imu_point ) = v_t + R_t (w x p_imu_point)
// w_meas is the raw gyro at the stamp; b_g the anchor state's gyro bias. S (3x3) may be
// rank-deficient: the non-holonomic factor only constrains y and z.
//
// Parameter blocks: q (4), v (3), bias (6) of the anchor state; p does not enter.
//
// Analytic Jacobians (they were automatic differentiation with 13-wide jets, a visible share of
// the window solve). With R_t = R_i E, E = dR(bg) = dR Exp(J_R_bg dbg), the right perturbation
// R_i Exp(theta), and dR(bg + d) = E Exp(J_eps d), J_eps = Jr(J_R_bg dbg) J_R_bg:
//   vehicle frame, a = R_i^T (v_i + g tau), u = E^T (a + dv(b)) = R_t^T v_t:
//     d/dtheta = E^T [a]x,  d/dv_i = R_t^T,  d/dbg = [u]x J_eps + E^T J_v_bg + [p]x,
//     d/dba = E^T J_v_ba,  each times R_imu_frame^T;
//   world frame, c = (w_meas - b_g) x p_imu_point:
//     d/dtheta = -R_i [dv(b) + E c]x,  d/dv_i = I,
//     d/dbg = R_i J_v_bg - R_t [c]x J_eps + R_t [p]x,  d/dba = R_i J_v_ba;
// then times S. tests/estimator/body_velocity_factor_test.cpp checks them against numeric
// differences on the manifold.
#pragma once

#include <ceres/cost_function.h>

#include "core/eigen_types.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est {

struct BodyVelocityMeasurement {
  enum class Frame { kVehicle, kWorld };
  Frame frame = Frame::kVehicle;        // kWorld: v_frame is in ENU and q_imu_frame unused
  Vec3 v_frame = Vec3::Zero();          // measured velocity of the point, measurement frame
  Mat3 sqrt_information = Mat3::Zero();  // S, measurement frame
  Vec3 p_imu_point = Vec3::Zero();
  Quat q_imu_frame = Quat::Identity();
  Vec3 gyro_raw = Vec3::Zero();  // rad/s, IMU frame, at the stamp
};

// The point's velocity in the measurement frame for a given state (no bias correction of the
// deltas: the state is at the stamp).
Vec3 PointVelocity(const BodyVelocityMeasurement& m, const Quat& q_world_imu,
                   const Vec3& v_world, const Vec3& gyro_bias);

// propagation covers [t_anchor, t] (zero steps when t is the anchor's stamp).
ceres::CostFunction* CreateBodyVelocityFactor(const BodyVelocityMeasurement& m,
                                              const ImuPreintegration& propagation);

// The same in a vehicle frame whose rotation the setup gives only approximately (an IMU mounted
// by hand): the frame is turned by c = (0, c_pitch, c_yaw) (rad, about the frame's own y and z
// axes: R_imu_frame Exp(c)), two more scalar blocks after the bias, estimated as globals of the
// window. A rotation about the frame's forward axis does not change a forward velocity, so roll
// is left out. r = S (Exp(c)^T v_c - v_measured); d/dc = S Exp(-c) [v_c]x Jr(-c) (y, z columns).
// InputError for a world-frame measurement.
ceres::CostFunction* CreateMountCorrectedBodyVelocityFactor(const BodyVelocityMeasurement& m,
                                                            const ImuPreintegration& propagation);

}  // namespace statebench::est
