// The part of a sensor-setup file (docs/sensor-setup.md) that every reader of a log needs: each
// sensor's type, id, mount and latency, read leniently (simulation parameters are neither needed
// nor checked, so a setup written by an import, which has none, reads as well as a simulator's).
// And the writer of such a minimal setup, for logs converted from elsewhere.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/se3.hpp"

namespace statebench::sensors {

struct SensorMount {
  std::string type;  // setup type name: imu, gnss, lidar, body_velocity, speed_encoder, ...
  std::string id;
  SE3 T_body_sensor;
  std::optional<double> latency_s;
  std::string estimator;  // the entry's `estimator:` block as flow YAML (empty: none)
  std::string comment;  // written as a comment line above the entry (may be empty)
};

// Throws InputError naming file:line:column on a missing type or id or a bad transform.
std::vector<SensorMount> ReadSensorMounts(const std::filesystem::path& setup_file);

// A setup file with `name` and the mounts (translation, and quaternion_wxyz unless the rotation
// is the identity; numbers in shortest round-trip form), preceded by `header_comment` (lines
// starting with '#').
std::string SensorMountsYaml(const std::string& name, const std::vector<SensorMount>& mounts,
                             const std::string& header_comment);

}  // namespace statebench::sensors
