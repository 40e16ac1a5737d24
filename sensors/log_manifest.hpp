// log.yaml, the manifest of a recorded log directory (docs/log-format.md): where the log comes
// from and which file holds which sensor's stream.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/geodetic.hpp"
#include "core/se3.hpp"
#include "sensors/log_format.hpp"

namespace statebench::sensors {

inline constexpr int kLogFormatVersion = 1;

struct LogStreamEntry {
  std::string id;  // sensor id of the measurements
  LogStreamType type = LogStreamType::kImu;
  std::string file;       // relative to the log directory (lidar: the sweep index CSV)
  std::size_t count = 0;  // measurements written (informative; the reader does not need it)
};

struct LogManifest {
  int version = kLogFormatVersion;
  std::string scenario;  // free text (scenario name, or the vehicle/drive of a real log)
  std::optional<std::uint64_t> seed;     // simulated logs
  std::optional<GeodeticPoint> origin;   // WGS84 anchor of the ENU world
  std::optional<std::string> setup;      // sensor-setup YAML file, relative
  std::optional<std::string> truth_csv;  // relative; truth_body.tum / truth_imu.tum beside it
  // The IMU's mount the truth's IMU columns were written through (simulated logs: the mount the
  // simulator used, which with a scenario's `mismatch:` is not the setup file's). Scores of the
  // log's estimates use it, as `statebench run` does.
  std::optional<SE3> truth_imu_mount;
  std::vector<LogStreamEntry> streams;   // the reader merges them in this order on ties
};

// Writes the manifest as YAML (numbers in shortest round-trip form); throws InputError when the
// file cannot be written.
void WriteLogManifest(const std::filesystem::path& file, const LogManifest& manifest);
// Reads and checks it; throws InputError "file:line:column: field 'streams[2].type': ...".
LogManifest ReadLogManifest(const std::filesystem::path& file);

}  // namespace statebench::sensors
