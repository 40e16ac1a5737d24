// A vehicle's sensor setup, loaded from YAML (format: docs/sensor-setup.md).
//
// Every entry has a type, an id, a rate, its mount T_body_sensor, a latency and the error
// parameters of its type. Bad input throws InputError naming file:line:column and the field.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/yaml_node.hpp"
#include "sensors/dual_antenna_heading.hpp"
#include "sensors/encoder_options.hpp"
#include "sensors/gnss_options.hpp"
#include "sensors/imu_options.hpp"
#include "sensors/lidar_options.hpp"
#include "sensors/sensor_spec.hpp"

namespace statebench::sensors {

// The variant alternatives of SensorOptions are in this order.
enum class SensorType : int {
  kImu = 0,
  kGnss,
  kWheelEncoders,
  kSpeedEncoder,
  kSteeringEncoder,
  kLidar
};

std::string_view SensorTypeName(SensorType type);  // "imu", "gnss", "wheel_encoders", ...

using SensorOptions = std::variant<ImuOptions, GnssOptions, WheelEncoderOptions,
                                   SpeedEncoderOptions, SteeringEncoderOptions, LidarOptions>;

struct SensorConfig {
  SensorSpec spec;
  SensorOptions options;
  std::string where;  // "file:line:column" of the entry, for later messages

  SensorType type() const { return static_cast<SensorType>(options.index()); }
};

struct SensorSetup {
  std::string name;
  std::string source;  // file it was loaded from
  std::vector<SensorConfig> sensors;
  std::vector<DualAntennaHeadingOptions> dual_antenna_headings;

  const SensorConfig* Find(std::string_view id) const;
  std::vector<const SensorConfig*> OfType(SensorType type) const;
};

SensorSetup LoadSensorSetup(const std::filesystem::path& path);
SensorSetup ParseSensorSetup(const YamlNode& root);

}  // namespace statebench::sensors
