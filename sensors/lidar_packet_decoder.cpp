// The reader of lidar packets files (lidar_packet_file.hpp).
#include <bit>
#include <cstring>
#include <string>

#include "core/error.hpp"
#include "sensors/file_bytes.hpp"
#include "sensors/lidar_packet_beams.hpp"
#include "sensors/lidar_packet_file.hpp"
#include "sensors/lidar_range_word.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void FailPackets(const fs::path& file, const std::string& what) {
  throw InputError(file.string() + ": " + what);
}

[[noreturn]] void FailPacketField(const fs::path& file, const std::string& field,
                                  const std::string& what) {
  FailPackets(file, "field '" + field + "': " + what);
}

// A packets file's header, checked against the file's size, and where its sections start.
struct PacketsHeader {
  std::uint64_t returns = 0, raw_points = 0;
  std::size_t intensity_bytes = 1;
  std::size_t mask_bytes = 0;  // per column
  const lidar_packets::BeamTable* beams = nullptr;
  const std::uint8_t *masks = nullptr, *words = nullptr, *intensities = nullptr, *raw = nullptr;
};

PacketsHeader ReadPacketsHeader(std::span<const std::uint8_t> bytes, const fs::path& file) {
  const std::size_t size = bytes.size();
  const std::uint8_t* in = bytes.data();
  constexpr auto& kMagic = lidar_packets::kMagic;
  if (size >= sizeof(kMagic) && std::memcmp(in, kMagic, sizeof(kMagic)) != 0) {
    FailPackets(file, "not a StateBench lidar packets file (its first bytes are not \"SBLIDPK\")");
  }
  if (size < lidar_packets::kElevationsBegin) {
    FailPackets(file, "truncated: " + std::to_string(size) + " bytes, the header alone takes " +
                          std::to_string(lidar_packets::kElevationsBegin) + " or more");
  }
  const auto version = GetLittleEndian<std::uint32_t>(in + lidar_packets::kVersionAt);
  if (version != lidar_packets::kVersion) {
    FailPacketField(
        file, "version",
        std::to_string(version) + ", this reader knows " + std::to_string(lidar_packets::kVersion));
  }
  const std::uint64_t channels = GetLittleEndian<std::uint16_t>(in + lidar_packets::kChannelsAt);
  const std::uint64_t columns = GetLittleEndian<std::uint32_t>(in + lidar_packets::kColumnsAt);
  lidar_packets::CheckBeamCounts(channels, columns, file);  // before sizes are computed from them
  PacketsHeader h;
  h.returns = GetLittleEndian<std::uint32_t>(in + lidar_packets::kPointsAt);
  h.raw_points = GetLittleEndian<std::uint32_t>(in + lidar_packets::kRawPointsAt);
  const std::uint8_t encoding = in[lidar_packets::kIntensityEncodingAt];
  if (encoding != lidar_packets::kIntensityByte && encoding != lidar_packets::kIntensityFloat) {
    FailPacketField(file, "intensity encoding", std::to_string(encoding) + ", expected 0 or 1");
  }
  h.intensity_bytes = encoding == lidar_packets::kIntensityByte ? 1 : 4;
  h.mask_bytes = lidar_packets::MaskBytes(channels);
  const std::uint64_t header = lidar_packets::HeaderBytes(channels);
  const std::uint64_t expected = header + columns * h.mask_bytes +
                                 (lidar_packets::kRangeWordBytes + h.intensity_bytes) * h.returns +
                                 lidar_packets::kRawPointBytes * h.raw_points;
  if (size != expected) {
    FailPackets(file, std::string(size < expected ? "truncated" : "too long") + ": " +
                          std::to_string(size) + " bytes, its header announces " +
                          std::to_string(h.returns) + " returns and " +
                          std::to_string(h.raw_points) + " raw points (" +
                          std::to_string(expected) + " bytes)");
  }
  h.beams = &lidar_packets::BeamTableOf(
      bytes.subspan(lidar_packets::kBeamSectionBegin, lidar_packets::BeamSectionBytes(channels)),
      file);
  lidar_packets::CheckDirections(
      *h.beams, GetLittleEndian<std::uint64_t>(in + lidar_packets::kChecksumAt), file);
  h.masks = in + header;
  h.words = h.masks + columns * h.mask_bytes;
  h.intensities = h.words + lidar_packets::kRangeWordBytes * h.returns;
  h.raw = h.intensities + h.intensity_bytes * h.returns;
  return h;
}

// The masks decide where each point goes: they must hold exactly the announced returns, of rings
// below C.
void CheckHitMasks(const PacketsHeader& h, const fs::path& file) {
  const int channels = h.beams->channels;
  const unsigned spare_bits = channels % 8 ? (0xFFu << (channels % 8)) & 0xFFu : 0u;
  std::uint64_t hits = 0;
  for (int c = 0; c < h.beams->columns; ++c) {
    const std::uint8_t* mask = h.masks + static_cast<std::size_t>(c) * h.mask_bytes;
    for (std::size_t j = 0; j < h.mask_bytes; ++j) hits += std::popcount(unsigned{mask[j]});
    if (mask[h.mask_bytes - 1] & spare_bits) {
      FailPacketField(file, "hit masks",
                      "column " + std::to_string(c) + " has a return of a ring beyond its " +
                          std::to_string(channels) + " channels");
    }
  }
  if (hits != h.returns) {
    FailPacketField(
        file, "hit masks",
        std::to_string(hits) + " returns, the header announces " + std::to_string(h.returns));
  }
}

float IntensityAt(const std::uint8_t* at, std::size_t intensity_bytes) {
  return intensity_bytes == 1 ? static_cast<float>(*at)
                              : std::bit_cast<float>(GetLittleEndian<std::uint32_t>(at));
}

// Every return, column by column, rings ascending, as the simulator made it (BeamReturn).
template <std::size_t kIntensityBytes>
void RebuildReturns(const PacketsHeader& h, LidarPoint* out) {
  const lidar_packets::BeamTable& beams = *h.beams;
  const std::uint8_t* word = h.words;
  const std::uint8_t* intensity = h.intensities;
  for (int c = 0; c < beams.columns; ++c) {
    const float t = beams.t_s[c];
    const Vec3* directions = beams.directions.data() + static_cast<std::size_t>(c) * beams.channels;
    const std::uint8_t* mask = h.masks + static_cast<std::size_t>(c) * h.mask_bytes;
    for (std::size_t j = 0; j < h.mask_bytes; ++j) {
      for (unsigned bits = mask[j]; bits != 0; bits &= bits - 1) {
        const auto ring = static_cast<std::uint16_t>(8 * j + std::countr_zero(bits));
        *out++ = BeamReturn(directions[ring], RangeFromWord(GetLittleEndian<std::uint32_t>(word)),
                            IntensityAt(intensity, kIntensityBytes), t, ring);
        word += lidar_packets::kRangeWordBytes;
        intensity += kIntensityBytes;
      }
    }
  }
}

// The raw points' x y z over the rebuilt ones.
void ApplyRawPoints(const PacketsHeader& h, std::vector<LidarPoint>& points, const fs::path& file) {
  const std::uint8_t* at = h.raw;
  std::int64_t last = -1;
  for (std::uint64_t i = 0; i < h.raw_points; ++i, at += lidar_packets::kRawPointBytes) {
    const std::uint32_t k = GetLittleEndian<std::uint32_t>(at);
    if (k >= h.returns || std::int64_t{k} <= last) {
      FailPacketField(file, "raw points",
                      "raw point " + std::to_string(i) + " names point " + std::to_string(k) +
                          " (after point " + std::to_string(last) + ", " +
                          std::to_string(h.returns) + " points)");
    }
    last = k;
    points[k].x = std::bit_cast<float>(GetLittleEndian<std::uint32_t>(at + 4));
    points[k].y = std::bit_cast<float>(GetLittleEndian<std::uint32_t>(at + 8));
    points[k].z = std::bit_cast<float>(GetLittleEndian<std::uint32_t>(at + 12));
  }
}

}  // namespace

std::vector<LidarPoint> DecodeLidarPackets(std::span<const std::uint8_t> bytes,
                                           const fs::path& file) {
  const PacketsHeader header = ReadPacketsHeader(bytes, file);
  CheckHitMasks(header, file);
  std::vector<LidarPoint> points(static_cast<std::size_t>(header.returns));
  if (header.intensity_bytes == 1) {
    RebuildReturns<1>(header, points.data());
  } else {
    RebuildReturns<4>(header, points.data());
  }
  ApplyRawPoints(header, points, file);
  return points;
}

std::vector<LidarPoint> ReadLidarPacketFile(const fs::path& file) {
  thread_local std::vector<std::uint8_t> bytes;
  ReadFileBytes(file, bytes);
  return DecodeLidarPackets(bytes, file);
}

}  // namespace statebench::sensors
