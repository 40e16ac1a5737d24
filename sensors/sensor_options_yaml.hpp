// YAML parsing of the type-specific part of sensor-setup entries (docs/sensor-setup.md). Each
// function checks that the entry holds only the common keys and its own, and validates ranges;
// errors throw InputError "file:line:column: field 'sensors[2].cep_m': ...".
#pragma once

#include "core/yaml_node.hpp"
#include "sensors/encoder_options.hpp"
#include "sensors/gnss_options.hpp"
#include "sensors/imu_options.hpp"
#include "sensors/lidar_options.hpp"

namespace statebench::sensors {

ImuOptions ParseImuOptions(const YamlNode& entry);
GnssOptions ParseGnssOptions(const YamlNode& entry);
WheelEncoderOptions ParseWheelEncoderOptions(const YamlNode& entry);
SpeedEncoderOptions ParseSpeedEncoderOptions(const YamlNode& entry);
SteeringEncoderOptions ParseSteeringEncoderOptions(const YamlNode& entry);
LidarOptions ParseLidarOptions(const YamlNode& entry);

// Checked numbers (core/option_table.hpp CheckedNumber): throw naming the field when out of
// range or not finite.
double NonNegative(const YamlNode& node);
double Positive(const YamlNode& node);
double InRange(const YamlNode& node, double lo, double hi);

}  // namespace statebench::sensors
