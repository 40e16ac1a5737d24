// Measurement types: what sensors (simulated or recorded) hand to the estimators.
//
// Every measurement carries the stamp at which it was taken and the stamp at which it arrived
// (stamp + latency); the stream delivers them ordered by arrival.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/time.hpp"

namespace statebench {

struct MeasurementHeader {
  std::string sensor_id;
  TimeNs stamp_ns = 0;    // when the quantity was measured
  TimeNs arrival_ns = 0;  // when it reached the estimator
};

// Raw IMU sample in the IMU frame (FLU): angular rate and specific force.
struct ImuSample {
  MeasurementHeader header;
  Vec3 gyro = Vec3::Zero();   // rad/s
  Vec3 accel = Vec3::Zero();  // m/s^2, specific force
};

enum class GnssFixStatus : int { kNone = 0, kSingle = 1, kRtkFloat = 2, kRtkFixed = 3 };

// A receiver's velocity of its antenna phase centre (from the carrier Doppler), local ENU at the
// fix, with the 1-sigma it reports per axis (m/s).
struct GnssVelocity {
  Vec3 v_enu = Vec3::Zero();
  Vec3 sigma_enu = Vec3::Zero();
};

// A receiver's position fix of its antenna phase centre, with its velocity when it gives one.
struct GnssFix {
  MeasurementHeader header;
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double altitude_m = 0.0;             // WGS84 ellipsoidal height
  Mat3 covariance_enu = Mat3::Zero();  // m^2, reported by the receiver
  GnssFixStatus status = GnssFixStatus::kNone;
  std::optional<GnssVelocity> velocity;
};

// Yaw and pitch of the baseline from a dual-antenna receiver, in the world frame (ENU, yaw
// counter-clockwise from east).
struct DualAntennaHeading {
  MeasurementHeader header;
  double yaw_rad = 0.0;
  double pitch_rad = 0.0;
  double yaw_sigma_rad = 0.0;
  double pitch_sigma_rad = 0.0;
};

// Wheel angular speeds, order front-left, front-right, rear-left, rear-right (rad/s).
struct WheelSpeeds {
  MeasurementHeader header;
  std::array<double, 4> omega_radps{};
};

// Longitudinal speed from a speed encoder (m/s).
struct VehicleSpeed {
  MeasurementHeader header;
  double speed_mps = 0.0;
};

// Road-wheel steering angle of the front axle (bicycle-equivalent), rad, positive to the left.
struct SteeringAngle {
  MeasurementHeader header;
  double angle_rad = 0.0;
};

struct LidarPoint {
  float x = 0.f, y = 0.f, z = 0.f;  // lidar frame, m
  float intensity = 0.f;
  float t = 0.f;       // seconds after the scan stamp
  std::uint16_t ring = 0;
};

// One sweep; header.stamp_ns is the time of the first column.
struct LidarScan {
  MeasurementHeader header;
  std::shared_ptr<const std::vector<LidarPoint>> points;
};

// Generic body-frame velocity odometry (wheel odometry, radar, ...), at the sensor frame.
struct BodyVelocity {
  MeasurementHeader header;
  Vec3 velocity = Vec3::Zero();  // m/s
  Vec3 angular_velocity = Vec3::Zero();  // rad/s
  Mat6 covariance = Mat6::Identity();  // (v, omega)
};

using Measurement = std::variant<ImuSample, GnssFix, DualAntennaHeading, WheelSpeeds, VehicleSpeed,
                                 SteeringAngle, LidarScan, BodyVelocity>;

inline const MeasurementHeader& HeaderOf(const Measurement& m) {
  return std::visit([](const auto& x) -> const MeasurementHeader& { return x.header; }, m);
}

}  // namespace statebench
