// Whole small binary files in and out of memory, and the little-endian integers of their headers:
// shared by the lidar sweep and packets files (lidar_sweep_file.hpp, lidar_packet_file.hpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace statebench::sensors {

// The whole file into `bytes` (replaced; one read). Throws InputError naming the file when it
// cannot be opened or read.
void ReadFileBytes(const std::filesystem::path& file, std::vector<std::uint8_t>& bytes);

// Writes `size` bytes as the whole file; throws InputError naming the file on failure.
void WriteFileBytes(const std::filesystem::path& file, const std::uint8_t* bytes, std::size_t size);

template <typename T>
void PutLittleEndian(std::uint8_t* out, T v) {
  for (std::size_t b = 0; b < sizeof(T); ++b) out[b] = static_cast<std::uint8_t>(v >> (8 * b));
}

template <typename T>
T GetLittleEndian(const std::uint8_t* in) {
  T v = 0;
  for (std::size_t b = 0; b < sizeof(T); ++b) v |= static_cast<T>(T{in[b]} << (8 * b));
  return v;
}

}  // namespace statebench::sensors
