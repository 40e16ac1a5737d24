// Plausibility checks on single measurements, before they reach an estimator's math. Each
// returns the reason a measurement must be rejected, or nullopt if it is usable. What depends
// on the estimator's state (stamps, gates, thresholds) is checked by the estimator itself.
#pragma once

#include <optional>

#include "core/measurements.hpp"
#include "core/option_table.hpp"
#include "estimator/estimator_diagnostics.hpp"

namespace statebench::est {

// Beyond the range of any automotive IMU (2000 deg/s, 20 g): absurd.
inline constexpr double kMaxAbsGyroRadps = 40.0;
inline constexpr double kMaxAbsAccelMps2 = 200.0;

std::optional<RejectReason> CheckImuSample(const ImuSample& sample);

// What an IMU on a ground vehicle can plausibly read, and how long its stream may pause. A
// sample beyond the limits (a shock that saturated the sensor, or a sensor gone mad) is rejected
// as `saturated`; set the limits just below the IMU's own range to catch its saturation. A pause
// longer than max_gap_s cannot be bridged by integrating the next sample: the estimator starts
// over from the sensors (counted as the IMU's `imu_gap` event).
struct ImuLimits {
  double max_accel_mps2 = 100.0;  // per axis, about 10 g
  double max_gyro_radps = 10.0;   // per axis, about 570 deg/s
  double max_gap_s = 0.5;
};

std::optional<RejectReason> CheckImuLimits(const ImuSample& sample, const ImuLimits& limits);
// The `imu_limits:` section of both estimators' options.
OptionTable<ImuLimits> ImuLimitsOptionTable();

// Non-finite values; latitude, longitude or altitude out of range (absurd, same limits as
// GnssFixToEnu); status kNone (no fix); covariance not symmetric positive definite.
std::optional<RejectReason> CheckGnssFix(const GnssFix& fix);

// Non-finite angles; |pitch| > pi/2 (absurd); yaw sigma not positive (invalid covariance).
// A non-positive pitch sigma is allowed and means "yaw only".
std::optional<RejectReason> CheckDualAntennaHeading(const DualAntennaHeading& heading);

// Non-finite speed; |speed| above 100 m/s (absurd).
std::optional<RejectReason> CheckVehicleSpeed(const VehicleSpeed& speed);
// Non-finite angle; |angle| above 1.2 rad (no road wheel steers 70 deg: absurd).
std::optional<RejectReason> CheckSteeringAngle(const SteeringAngle& angle);
// A scan without a point buffer (absurd). Empty scans and NaN points are the odometry's to
// count: they are rejected there with the detail.
std::optional<RejectReason> CheckLidarScan(const LidarScan& scan);

// Non-finite velocity or covariance; faster than 100 m/s (absurd); a velocity variance that is
// negative or zero (invalid covariance: an unmeasured component has a large variance).
std::optional<RejectReason> CheckBodyVelocity(const BodyVelocity& velocity);

}  // namespace statebench::est
