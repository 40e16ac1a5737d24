// The beam section of a lidar packets file (lidar_packet_file.hpp, bytes 29 to 52 + 8 C) and the
// tables regenerated from it: every beam's direction and every column's firing time, computed by
// LidarBeamModel's own functions (cos and sin of the C library) and kept per thread for the next
// sweep of the same lidar, with a checksum of the directions' bits that the file also carries
// (bytes 20-27): a reader whose cos or sin round differently from the writer's would rebuild
// other points, and says so instead.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "core/eigen_types.hpp"
#include "sensors/lidar_beam_model.hpp"
#include "sensors/lidar_packet_layout.hpp"

namespace statebench::sensors::lidar_packets {

inline constexpr int kMaxChannels = 1024;
inline constexpr int kMaxColumns = 1 << 20;
inline constexpr std::int64_t kMaxBeams = 1 << 21;

// Bytes of the beam section for C channels.
inline std::size_t BeamSectionBytes(std::size_t channels) {
  return kElevationsBegin - kBeamSectionBegin + 8 * channels;
}

// Throws InputError naming `file` and the field unless 1 <= channels <= kMaxChannels,
// 1 <= columns <= kMaxColumns and channels * columns <= kMaxBeams.
void CheckBeamCounts(std::uint64_t channels, std::uint64_t columns,
                     const std::filesystem::path& file);

// The model's beam section, or empty when it is outside the format's limits.
std::vector<std::uint8_t> BeamSectionOf(const LidarBeamModel& beams);

struct BeamTable {
  int channels = 0;
  int columns = 0;
  std::vector<Vec3> directions;  // [column * channels + ring]
  std::vector<float> t_s;        // by column
  std::uint64_t checksum = 0;    // FNV-1a over the bits of the directions, in table order
};

// The tables of a beam section (`section` holds BeamSectionBytes(C) bytes, C from its bytes 1-2),
// valid until the next call on this thread. Throws InputError naming `file` and the field when
// the section's model is outside the limits (channels, columns, rate, a non-finite angle).
// A reader compares the table's checksum with the file's (CheckDirections).
const BeamTable& BeamTableOf(std::span<const std::uint8_t> section,
                             const std::filesystem::path& file);

// Throws InputError naming `file` unless the file's checksum is the table's.
void CheckDirections(const BeamTable& table, std::uint64_t file_checksum,
                     const std::filesystem::path& file);

}  // namespace statebench::sensors::lidar_packets
