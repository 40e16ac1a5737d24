// Options of the factors beyond IMU and GNSS: lidar odometry, the kinematic (encoder) factor and
// the parameter-free vehicle motion constraints (non-holonomic, zero velocity). Part of
// FactorGraphOptions; YAML keys in docs/estimator-config.md.
//
// `use` of a sensor-driven factor:
//   auto: used when the sensor setup has the sensors it needs (the default: one config serves
//         every vehicle, plug-and-play);
//   on:   required: a setup without them is an InputError when the estimator is built;
//   off:  not used; the measurements are counted as unused in the diagnostics.
#pragma once

#include <string>

#include "estimator/lidar_odometry.hpp"
#include "estimator/robust_kernel.hpp"

namespace statebench::est {

enum class FactorUse { kAuto, kOn, kOff };

// "auto", "on"/"true", "off"/"false"; InputError otherwise.
FactorUse ParseFactorUse(const std::string& value);
const char* FactorUseName(FactorUse use);

// Where the lidar odometry's motion prediction (initial guess and deskew within the sweep) comes
// from:
//   imu:               the estimator's own window and IMU-rate propagation (each estimator
//                      registers its scans itself);
//   constant_velocity: the odometry's own constant-velocity model, as KISS-ICP and the paper run
//                      it. The registrations then depend on the scans and the odometry's
//                      options only, so the estimators of one run with the same lidars and
//                      odometry options share one registration per scan
//                      (shared_lidar_odometry.hpp);
//   gyro:              rotations from the raw gyro, translations from the constant-velocity
//                      model: shared like constant_velocity (the raw samples are the same for
//                      every estimator).
enum class LidarPriorSource { kImu, kConstantVelocity, kGyro };
LidarPriorSource ParseLidarPriorSource(const std::string& value);  // InputError otherwise
const char* LidarPriorSourceName(LidarPriorSource source);

struct LidarFactorOptions {
  FactorUse use = FactorUse::kAuto;
  LidarOdometryOptions odometry;
  // The ICP's Hessian covariance only knows the point noise; scan-to-map registration errors
  // are correlated and larger. The factor's covariance is the ICP covariance times
  // covariance_scale, floored per axis at these sigmas (lidar frame, one scan period).
  double covariance_scale = 10.0;
  double min_sigma_translation_m = 0.005;
  double min_sigma_rotation_rad = 0.0005;
  RobustKernel kernel;
  // A registration whose translation differs from the IMU prediction by more than this
  // (per scan period) is rejected as an ICP failure.
  double max_prior_deviation_m = 1.0;
  LidarPriorSource motion_prior = LidarPriorSource::kImu;
  // The lidar's mount rotation against the IMU (the setup's T_imu_lidar is measured by hand):
  // roll, pitch and yaw of the lidar frame (R_imu_lidar Exp(c)) as three globals of the window,
  // prior N(0, sigma^2), held within +-mount_max_deg; the factors' and the IMU prior's X is turned
  // by them, each lidar's by its own (with merge_scans: the first one's frame, the merged
  // scan's). Off: the setup's rotation is taken as exact. On by default
  // (docs/calibration-states.md).
  bool estimate_mount = true;
  double mount_prior_sigma_deg = 1.0;
  double mount_max_deg = 5.0;
  // Several lidars: merge their scans into one per period in the first lidar's frame through
  // the setup's mounts and register that (one odometry, one factor per period). Off: each lidar
  // is registered on its own (its own odometry, factors and mount globals), which does not
  // depend on the lidars' relative mounts being exact (lidar_front_end.hpp).
  bool merge_scans = false;
};

// Kinematic factor (paper): the rear-axle speed V from the speed encoder and the front
// road-wheel angle delta from the steering encoder integrated between states with the yaw rate
//   omega = V cos(delta_r) (tan(delta) - tan(delta_r)) / l,   delta_r = -rear_steering_ratio delta
// (delta_r = 0 for front steering), l the distance along the body x axis between the steering
// encoder (front axle) and the speed encoder (rear axle) mounts. The planar motion of the
// rear-axle frame over period_s becomes a relative-pose factor (x, y, yaw; z, roll and pitch
// free) moved to the IMU through the static transform.
struct KinematicFactorOptions {
  FactorUse use = FactorUse::kAuto;
  double period_s = 0.1;
  double speed_sigma_mps = 0.02;     // white error of one speed sample
  // Relative scale error per period. The wheel radius itself is calibrated online
  // (encoder_scale_calibration.hpp); what is left is treated as independent per period, with a
  // sigma large enough that the kinematic factor does not hold the distance against the other
  // sensors (measured on setup 2: 0.01 kept a 1 % radius error, 0.03 lets it calibrate).
  double speed_scale_sigma = 0.03;
  double steering_sigma_rad = 0.005; // offset and noise of the steering angle
  double lateral_sigma_mps = 0.05;   // side slip the model ignores, as a velocity
  // Tyre slip grows with the lateral acceleration a = V^2 kappa: the rear axle's side slip
  // angle and the departure of the yaw rate from the kinematic one are taken as
  // slip_per_lateral_accel * |a| (rad), so sigma_lat += V * that and the steering angle's
  // sigma is widened by it (about 0.01 rad per m/s^2 covers cars and light vehicles).
  double slip_per_lateral_accel = 0.01;
  double vertical_sigma_mps = 0.05;  // motion off the rear axle's x-y plane (suspension, grade)
  double rear_steering_ratio = 0.0;  // 4-wheel steering: rear angle = -ratio * front angle
  double max_gap_s = 0.2;            // encoder gap that breaks the integration
};

// Non-holonomic constraint: a road vehicle does not slide sideways or leave the road, so the
// velocity of the rear-axle centre has zero lateral and vertical components (loose sigmas for
// slip and suspension). The point is the speed encoder's mount when the setup has one, else the
// body-frame origin (the road below the CG; right for a symmetric 4-wheel-steered shuttle).
// Not added while the kinematic factor is active (it already holds the lateral constraint).
struct NonHolonomicOptions {
  bool enabled = true;
  double rate_hz = 10.0;
  // sigma_lateral = lateral_sigma_mps + slip_per_lateral_accel * |v| * |v omega_z| (slip in
  // turns, as KinematicFactorOptions::slip_per_lateral_accel).
  double slip_per_lateral_accel = 0.01;
  double lateral_sigma_mps = 0.1;
  double vertical_sigma_mps = 0.05;
  // The IMU's mount rotation about the vehicle's lateral and vertical axes (the setup's
  // T_body_imu is measured by hand) as two globals of the window, prior N(0, sigma^2), held
  // within +-mount_max_deg: the constraint's frame is turned by them. Off: the setup's rotation
  // is taken as exact and its uncertainty only added to the output covariance (consider).
  bool estimate_mount = false;
  double mount_prior_sigma_deg = 1.0;
  double mount_max_deg = 5.0;
};

// Zero-velocity factor when the vehicle stands still: the IMU is quiet over window_s (per-axis
// standard deviations below the thresholds, of the raw samples or, with an engine running, of
// their low band below ~3 Hz: imu_band_split.hpp, lowpass_s) and a speed reading says so: the
// speed encoder, when there is one, reads zero; else the receiver's Doppler velocity, when it
// gives one, averages below max_doppler_speed_mps over doppler_window_s; else the estimated
// speed is below max_estimated_speed_mps (a quiet IMU alone cannot tell standing from
// cruising). Without an encoder the acceleration the IMU measures (mean specific force rotated
// to the world with the estimated attitude, bias and gravity removed) must also be below
// max_acceleration_mps2: a smooth start from a stop keeps the IMU quiet, and the factor would
// otherwise hold the speed it is tested on at zero while the vehicle drives off.
struct ZeroVelocityOptions {
  bool enabled = true;
  double rate_hz = 10.0;
  double window_s = 0.3;
  double max_gyro_std_radps = 0.005;
  double max_accel_std_mps2 = 0.06;
  // The low band's filter: two moving averages of lowpass_s (0: the raw samples only).
  double lowpass_s = 0.1;
  double max_encoder_speed_mps = 0.005;
  // The mean of the Doppler velocities (horizontal, ENU) over the window: a 4 Hz receiver with
  // 0.07 m/s per axis gives 4 readings a second, their mean 0.035 m/s.
  double doppler_window_s = 1.0;
  double max_doppler_speed_mps = 0.2;
  // When that mean also agrees with zero within this many of its own sigmas (per axis, the
  // reported sigmas / sqrt(n); 2 degrees of freedom: 3 keeps 98.9 % of true standstills), a creep
  // the test cannot rule out is of the order of that sigma: it is the factor's sigma (within
  // [sigma_mps, sigma_without_encoder_mps]); 4 readings of 0.07 m/s give 0.035 m/s. 0: never.
  double doppler_agreement_sigmas = 3.0;
  // Without an encoder or Doppler: the estimated speed below max_estimated_speed_mps plus this
  // many of its sigmas (0: below max_estimated_speed_mps only).
  double max_estimated_speed_mps = 0.3;
  double estimated_speed_sigmas = 3.0;
  double max_acceleration_mps2 = 0.3;
  double sigma_mps = 0.005;
  // Without an encoder the test cannot rule out a creep below max_estimated_speed_mps: the
  // factor's sigma is then this (a third of that speed), not sigma_mps, unless the Doppler
  // mean agrees with zero (doppler_agreement_sigmas).
  double sigma_without_encoder_mps = 0.1;
};

}  // namespace statebench::est
