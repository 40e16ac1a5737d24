// Gravity direction and velocity of a moving vehicle from its IMU and a body-frame velocity
// odometry (wheel odometry, a speed encoder): the start of a setup without an absolute-position
// sensor when it is not standing still.
//
// The IMU velocity in the IMU frame at an odometry stamp t_k is, with omega the gyro rate and
// (p, Q) the odometry frame's mount in the IMU frame,
//   u_k = Q v_frame - omega x p.
// With the IMU preintegrated from t_a (dR_k, dv_k; imu_preintegration.hpp) the world velocity
// obeys R_k u_k = R_a u_a + g tau_k + R_a dv_k, tau_k = t_k - t_a, so in the IMU frame at t_a
//   u_a + tau_k G = dR_k u_k - dv_k,        G = R_a^T g  (gravity seen from the IMU at t_a),
// linear in the six unknowns (u_a, G): a weighted least-squares line fit over the odometry
// samples of the window, whatever the vehicle did meanwhile (turns included). The up axis at t_a
// is -G / |G|. The accelerometer bias enters G as -b_a (tilt error |b_a| / g) and cancels when the
// velocity is carried to the window's end with the same deltas. Unmeasured components (variance
// of 100 (m/s)^2 or more, as BodyVelocityFrontEnd) are taken as zero with kUnmeasuredSigmaMps:
// a ground vehicle's odometry point does not slide sideways or jump.
#pragma once

#include <optional>
#include <span>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/se3.hpp"
#include "core/time.hpp"
#include "estimator/imu_noise.hpp"

namespace statebench::est {

// One odometry sample as the initialiser keeps it.
struct OdometryVelocity {
  TimeNs t_ns = 0;
  Vec3 v_frame = Vec3::Zero();  // velocity of the odometry point in its frame, m/s
  // Per component, m/s; at least kUnmeasuredVariance (BodyVelocityFrontEnd): not measured.
  Vec3 variance = Vec3::Zero();
  Vec3 p_imu_point = Vec3::Zero();  // the odometry frame's mount in the IMU frame
  Quat q_imu_frame = Quat::Identity();
};

// The sample of an odometry measuring v_frame (variance per component) in the frame at T_imu_frame.
inline OdometryVelocity MakeOdometryVelocity(TimeNs t_ns, const Vec3& v_frame,
                                             const Vec3& variance, const SE3& T_imu_frame) {
  OdometryVelocity o;
  o.t_ns = t_ns;
  o.v_frame = v_frame;
  o.variance = variance;
  o.p_imu_point = T_imu_frame.translation();
  o.q_imu_frame = T_imu_frame.rotation();
  return o;
}

struct OdometryAlignment {
  TimeNs t_a_ns = 0;               // the window's first odometry stamp
  TimeNs t_b_ns = 0;               // and its last
  Vec3 up_imu = Vec3::UnitZ();     // world up in the IMU frame at t_a (unit)
  double gravity_mps2 = 0.0;       // |G|, a check of the fit (g if all is well)
  Vec3 u_imu = Vec3::Zero();       // IMU velocity in the IMU frame at t_a, m/s
  Mat6 covariance = Mat6::Zero();  // of (u_a, G) from the odometry noise
};

inline constexpr double kUnmeasuredSigmaMps = 0.2;

// The fit over `odometry` (stamp order, at least three samples spanning some time, every stamp
// covered by `imu`, the IMU samples in stamp order); t_a is the first odometry stamp. The gyro
// bias is gyro_bias, the accel bias is taken as zero. nullopt if the samples do not determine
// the line or the IMU does not cover them.
std::optional<OdometryAlignment> AlignWithOdometry(std::span<const ImuSample> imu,
                                                   std::span<const OdometryVelocity> odometry,
                                                   const ImuNoise& noise, const Vec3& gyro_bias);

// The IMU velocity in the IMU frame at an odometry sample's stamp, with gyro the (bias-corrected)
// rate then, and its covariance (unmeasured components as above).
Vec3 ImuVelocityOf(const OdometryVelocity& v, const Vec3& gyro, Mat3* covariance);

}  // namespace statebench::est
