// Navigation state of the IMU frame and its uncertainty, as every estimator outputs it.
#pragma once

#include <cstdint>

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

// What an estimate rests on, so that a vehicle or a report can tell a sound estimate from a
// guess (names as written in estimate.csv: EstimateStatusName).
enum class EstimateStatus : std::uint8_t {
  kGlobal,         // an absolute position (GNSS) accepted within the last few seconds
  kDeadReckoning,  // no absolute position accepted for a while: IMU (and encoders, lidar) only
  kRecovering,     // re-initialised after the estimator found itself lost, a few seconds ago
  kLocal,          // the setup has no absolute position sensor: a local frame
};

inline const char* EstimateStatusName(EstimateStatus status) {
  switch (status) {
    case EstimateStatus::kGlobal:
      return "global";
    case EstimateStatus::kDeadReckoning:
      return "dead_reckoning";
    case EstimateStatus::kRecovering:
      return "recovering";
    case EstimateStatus::kLocal:
      return "local";
  }
  return "unknown";
}

struct StateEstimate {
  EstimateStatus status = EstimateStatus::kGlobal;
  NavState state;
  Mat15 covariance = Mat15::Identity();
  double latitude_deg = 0.0;  // WGS84 position of the IMU
  double longitude_deg = 0.0;
  double altitude_m = 0.0;
};

}  // namespace statebench
