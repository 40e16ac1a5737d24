// One lidar sweep as a StateBench sweep file (`.sweep`, docs/log-format.md "Sweep files"):
// every field of every point kept bit for bit, in about a fifth of a binary PCD's bytes. Each
// field is transformed (lidar_sweep_codec.hpp) and compressed on its own as one zstd frame with
// its content size and checksum. Layout (integers little-endian):
//
//   offset  bytes  content
//   0       8      magic "SBSWEEP" and a zero byte
//   8       4      format version: 1
//   12      4      n, the number of points (at most kMaxSweepFilePoints)
//   16      24     6 x uint32: the bytes of each field's frame, in the order t ring x y z intensity
//   40      ...    the 6 frames in that order, each decompressing to the field's byte planes
//                  (4 n bytes, ring 2 n); the file ends with the last frame
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/measurements.hpp"

namespace statebench::sensors {

inline constexpr std::uint32_t kMaxSweepFilePoints = 1u << 26;

// Throws InputError naming the file when it cannot be written or holds too many points.
void WriteLidarSweepFile(const std::filesystem::path& file, const std::vector<LidarPoint>& points);

// Throws InputError naming the file (and the field, for a bad frame) when it is missing, too
// short, not a sweep file, of another version, or a field's frame is truncated, corrupt (zstd's
// checksum) or does not hold the field's bytes for the announced points.
std::vector<LidarPoint> ReadLidarSweepFile(const std::filesystem::path& file);

}  // namespace statebench::sensors
