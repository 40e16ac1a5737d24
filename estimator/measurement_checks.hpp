// Plausibility checks on single measurements, before they reach an estimator's math. Each
// returns the reason a measurement must be rejected, or nullopt if it is usable. What depends
// on the estimator's state (stamps, gates, thresholds) is checked by the estimator itself.
#pragma once

#include <optional>

#include "core/measurements.hpp"
#include "estimator/estimator_diagnostics.hpp"

namespace statebench::est {

// Beyond the range of any automotive IMU (2000 deg/s, 20 g): absurd.
inline constexpr double kMaxAbsGyroRadps = 40.0;
inline constexpr double kMaxAbsAccelMps2 = 200.0;

std::optional<RejectReason> CheckImuSample(const ImuSample& sample);

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
