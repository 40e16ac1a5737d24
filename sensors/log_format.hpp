// The recorded-log format (docs/log-format.md): one CSV file per sensor in a folder per
// measurement type, one PCD file per lidar sweep, a log.yaml manifest. This file holds what the
// writer and the reader share: stream types, their folders and column names.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/measurements.hpp"

namespace statebench::sensors {

// One per Measurement alternative, in the same order.
enum class LogStreamType : int {
  kImu = 0,
  kGnss,
  kDualAntennaHeading,
  kWheelSpeeds,
  kVehicleSpeed,
  kSteeringAngle,
  kLidar,
  kBodyVelocity
};

// "imu", "gnss", "dual_antenna_heading", "wheel_speeds", "vehicle_speed", "steering_angle",
// "lidar", "body_velocity" (the manifest's `type`).
std::string_view LogStreamTypeName(LogStreamType type);
std::optional<LogStreamType> ParseLogStreamType(std::string_view name);
// Folder of the type's files: imu, gnss, heading, wheels, speed, steering, lidar, body_velocity.
std::string_view LogStreamFolder(LogStreamType type);
LogStreamType StreamTypeOf(const Measurement& m);

// Column names of the type's CSV file, in order (header line "#" + names joined by ','). For
// lidar this is the per-sensor index of sweeps (stamp, arrival, point count, PCD file name).
const std::vector<std::string>& LogCsvColumns(LogStreamType type);
// The optional columns a gnss file may add after LogCsvColumns(kGnss): the receiver's ENU
// velocity and its 1-sigma per axis (ve, vn, vu, sigma_ve, sigma_vn, sigma_vu).
const std::vector<std::string>& GnssVelocityCsvColumns();

// The columns of one log CSV file: its type's, plus for gnss optionally the velocity ones.
struct LogCsvLayout {
  LogStreamType type = LogStreamType::kImu;
  bool gnss_velocity = false;  // GnssVelocityCsvColumns() after the gnss columns

  std::vector<std::string> Columns() const;
};

// GnssFixStatus as text: none, single, rtk_float, rtk_fixed.
std::string_view GnssStatusName(GnssFixStatus status);
std::optional<GnssFixStatus> ParseGnssStatus(std::string_view name);

}  // namespace statebench::sensors
