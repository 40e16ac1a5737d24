// The registrations of a shared lidar odometry as a file, so that a later run with the same
// inputs reads them instead of registering again (the stage cache's `lidar_odometry` stage,
// docs/sweeps.md). Binary, little-endian, every field at full precision: a result read back is
// the result written, bit for bit.
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include "core/time.hpp"
#include "estimator/lidar_odometry.hpp"

namespace statebench::est {

struct RecordedRegistration {
  TimeNs stamp_ns = 0;
  std::size_t points = 0;  // of the scan registered (a replay checks it)
  LidarOdometryResult result;
};

// Throws InputError naming the file when it cannot be written.
void WriteRegistrations(const std::filesystem::path& file,
                        const std::vector<RecordedRegistration>& registrations);
// Throws InputError naming the file and the record when it cannot be read or is malformed.
std::vector<RecordedRegistration> ReadRegistrations(const std::filesystem::path& file);

}  // namespace statebench::est
