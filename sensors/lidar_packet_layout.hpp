// Offsets and sizes of a lidar packets file (the layout is in lidar_packet_file.hpp), shared by
// its writer and its reader.
#pragma once

#include <cstddef>
#include <cstdint>

namespace statebench::sensors::lidar_packets {

inline constexpr char kMagic[8] = {'S', 'B', 'L', 'I', 'D', 'P', 'K', '\0'};
inline constexpr std::uint32_t kVersion = 1;

inline constexpr std::size_t kVersionAt = 8;
inline constexpr std::size_t kPointsAt = 12;
inline constexpr std::size_t kRawPointsAt = 16;
inline constexpr std::size_t kChecksumAt = 20;
inline constexpr std::size_t kIntensityEncodingAt = 28;
inline constexpr std::size_t kBeamSectionBegin = 29;  // the beam model, lidar_packet_beams.hpp
inline constexpr std::size_t kChannelsAt = 30;
inline constexpr std::size_t kColumnsAt = 32;
inline constexpr std::size_t kElevationsBegin = 52;

inline constexpr std::size_t kRangeWordBytes = 4;
inline constexpr std::size_t kRawPointBytes = 16;  // uint32 index, float32 x y z

enum IntensityEncoding : std::uint8_t { kIntensityByte = 0, kIntensityFloat = 1 };

// Bytes of a column's hit mask.
inline std::size_t MaskBytes(std::size_t channels) { return (channels + 7) / 8; }

// Bytes from the start of the file to the hit masks: the header with C elevations.
inline std::size_t HeaderBytes(std::size_t channels) { return kElevationsBegin + 8 * channels; }

}  // namespace statebench::sensors::lidar_packets
