// Navigation state of the IMU frame and its uncertainty, as every estimator outputs it.
#pragma once

#include "core/eigen_types.hpp"
#include "core/time.hpp"

namespace statebench {

// Gravity in the local ENU world frame (m/s^2). The world is treated as flat and non-rotating.
inline constexpr double kGravity = 9.80665;
inline const Vec3 kGravityWorld(0.0, 0.0, -kGravity);

struct NavState {
  TimeNs t_ns = 0;
  Quat q_world_imu = Quat::Identity();
  Vec3 p_world = Vec3::Zero();  // IMU origin in ENU, m
  Vec3 v_world = Vec3::Zero();  // IMU velocity in ENU, m/s
  Vec3 gyro_bias = Vec3::Zero();   // rad/s, IMU frame
  Vec3 accel_bias = Vec3::Zero();  // m/s^2, IMU frame
};

// Error-state ordering of the 15x15 covariance: [rotation, position, velocity, gyro bias, accel
// bias], 3 each. The rotation error is a right perturbation, R = R_hat Exp(dtheta) (IMU frame);
// position and velocity errors are in the world frame.
enum StateBlock : int {
  kRotationIndex = 0,
  kPositionIndex = 3,
  kVelocityIndex = 6,
  kGyroBiasIndex = 9,
  kAccelBiasIndex = 12,
};

struct StateEstimate {
  NavState state;
  Mat15 covariance = Mat15::Identity();
  double latitude_deg = 0.0;  // WGS84 position of the IMU
  double longitude_deg = 0.0;
  double altitude_m = 0.0;
};

}  // namespace statebench
