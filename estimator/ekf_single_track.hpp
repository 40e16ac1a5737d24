// The paper's baseline (Prakash et al. 2023): an extended Kalman filter on a dynamic single-track
// (bicycle) vehicle model, behind the same Estimator interface as the factor graph.
//
// Frames: the body frame of the sensor setup (FLU, origin on the road below the centre of
// gravity, CG); the IMU at T_body_imu. The vehicle is planar: roll = pitch = 0, the altitude of
// the body origin a separate scalar random-walk filter on the GNSS heights.
//
// State (8): [x, y] body origin in ENU (m), yaw psi of the body x axis (rad, wrapped to
//   (-pi, pi]), vx, vy body-frame velocity of the CG (m/s; vy/vx is the side slip), yaw rate r
//   (rad/s), gyro z bias b_g (rad/s, body z), longitudinal accel bias b_a (m/s^2, body x).
// Process (continuous, integrated in substeps of at most 2.5 ms, midpoint rule; Jacobian by
//   central differences):
//   x' = vx cos psi - vy sin psi,  y' = vx sin psi + vy cos psi,  psi' = r,
//   vx' = a_x - b_a + r vy + r^2 l_x      (a_x: IMU specific force along body x, input; the
//                                           r^2 l_x term moves it from the IMU to the CG),
//   vy', r': single-track lateral dynamics with linear tyres and steering input delta
//     (rear angle -ratio delta):  alpha_f = delta_f - (vy + lf r)/vx, alpha_r = delta_r -
//     (vy - lr r)/vx,  vy' = (Cf alpha_f + Cr alpha_r)/m - r vx,  r' = (lf Cf alpha_f -
//     lr Cr alpha_r)/Iz;  below blend_low_speed_mps replaced by a relaxation towards the
//     kinematic bicycle (vy_kin = vx (lf tan delta_r + lr tan delta_f)/L, r_kin = vx (tan
//     delta_f - tan delta_r)/L, time constant kinematic_time_constant_s), linearly blended
//     up to blend_high_speed_mps, so the model stays well posed at standstill; kinematic when
//     reversing.
//   Without a steering encoder in the setup: r' = 0 (a random walk the gyro drives) and vy
//     relaxes to 0 (no side slip) with kinematic_time_constant_s.
// Updates: IMU gyro z (body) as r + b_g, every sample; speed encoder as vx - r l_y at the
//   sensor; body_velocity (odometry) as the measured components of its origin's velocity in its
//   frame, R_body_sensor^T (vx - r l_y, vy + r l_x, 0), each with its reported variance
//   (ekf_point_velocity.hpp); GNSS antenna position (x, y) + R(psi) l_xy with the antenna lever arm, moved back
//   to the fix stamp by the current velocity when it arrives late; GNSS height in the altitude
//   filter; dual-antenna heading (DualAntennaHeading of a dual_antennas entry) as psi plus the
//   baseline's yaw in the body frame. Steering angles are inputs (held). Gates: GNSS covariance
//   threshold, chi-square gates on GNSS and speed innovations (reopened after gate_reset_s of
//   rejections).
// Initialisation: the ENU origin is the first accepted fix; once the first antenna has moved
//   course_min_distance_m and far enough for the chord's yaw sigma (sqrt(2) sigma_h / distance)
//   to be below course_max_yaw_sigma_rad, yaw = course of that displacement (flipped when the
//   encoder speed is negative; its variance the chord's plus init_yaw_sigma_rad^2), vx = encoder
//   speed (or displacement / time without encoder).
//   Without a GNSS antenna in the setup: a local frame (ekf_local_start.cpp), started as the
//   factor graph's (state_initializer.hpp): the IMU at 0 and the body x axis along x (yaw 0),
//   from a still period (gyro bias) or, moving, from 1 s of odometry (speed encoder,
//   body_velocity) and the IMU; the body-x component of gravity the start sees becomes the
//   longitudinal accel bias (the model has no pitch). Its WGS84 output is that frame placed at
//   latitude, longitude and height 0 and its status `local`.
// Output: IMU pose from the planar state (roll = pitch = 0), ENU velocity of the IMU, biases in
//   the IMU frame, and the covariance mapped into the 15x15 ordering of core/state.hpp; the
//   components the filter does not estimate (roll, pitch, vertical velocity, the other bias
//   axes) get the fixed sigmas of the options. StateAt serves the last history_s of IMU time.
// Not used (rejected as kUnsupportedSensor): wheel speeds, lidar. Two antennas without a heading
//   message are used as two position sensors.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/geodetic.hpp"
#include "estimator/ekf_options.hpp"
#include "estimator/estimator.hpp"
#include "estimator/estimator_config.hpp"

namespace statebench::est {

class EkfSingleTrackEstimator final : public Estimator {
 public:
  // Throws InputError if the options are not valid.
  EkfSingleTrackEstimator(const EstimatorSensorSetup& setup, const EkfOptions& options);
  ~EkfSingleTrackEstimator() override;
  EkfSingleTrackEstimator(const EkfSingleTrackEstimator&) = delete;
  EkfSingleTrackEstimator& operator=(const EkfSingleTrackEstimator&) = delete;

  std::string name() const override { return "ekf"; }
  void Add(const Measurement& measurement) override;
  std::optional<StateEstimate> StateAt(TimeNs t_ns) const override;
  EstimatorDiagnostics diagnostics() const override;
  void SetVerdictObserver(VerdictObserver observer) override;

  // The ENU origin; nullopt until known.
  std::optional<GeodeticPoint> origin() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace statebench::est
