#include "sensors/lidar_packet_file.hpp"

#include <bit>
#include <cstring>
#include <string>

#include "core/error.hpp"
#include "sensors/file_bytes.hpp"
#include "sensors/lidar_packet_beams.hpp"
#include "sensors/lidar_range_word.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;
using lidar_packets::BeamSectionBytes;
using lidar_packets::BeamTable;

constexpr char kPacketMagic[8] = {'S', 'B', 'L', 'I', 'D', 'P', 'K', '\0'};
constexpr std::uint32_t kPacketVersion = 1;
constexpr std::size_t kPointsAt = 12, kRawPointsAt = 16, kIntensityEncodingAt = 20,
                      kChannelsAt = 22, kColumnsAt = 24;
constexpr std::size_t kRawPointBytes = 16;
// How far from the guess (in units of the word's last bit) the encoder looks for a word that
// rebuilds the point: the guess is within a float's rounding (2^-24) of the range, 32 units.
constexpr std::int64_t kRangeWordSearch = 64;

std::uint32_t FloatBits(float v) { return std::bit_cast<std::uint32_t>(v); }

std::size_t MaskBytes(int channels) { return (static_cast<std::size_t>(channels) + 7) / 8; }

bool IsWholeByte(float v) {
  return v >= 0.f && v <= 255.f && FloatBits(static_cast<float>(static_cast<int>(v))) == FloatBits(v);
}

bool Rebuilds(const Vec3& d, std::uint32_t word, const LidarPoint& p) {
  const LidarPoint q = BeamReturn(d, RangeFromWord(word), 0.f, 0.f, 0);
  return FloatBits(q.x) == FloatBits(p.x) && FloatBits(q.y) == FloatBits(p.y) &&
         FloatBits(q.z) == FloatBits(p.z);
}

// A word whose range rebuilds p's x y z on beam d, searched outwards from the range p implies.
std::optional<std::uint32_t> RangeWordOf(const Vec3& d, const LidarPoint& p) {
  const double guess = double{p.x} * d.x() + double{p.y} * d.y() + double{p.z} * d.z();
  if (!(guess > 0.0) || !std::isfinite(guess)) return std::nullopt;
  constexpr int kDropped = 52 - kRangeWordFractionBits;
  const std::uint64_t rounded =
      (std::bit_cast<std::uint64_t>(guess) + (std::uint64_t{1} << (kDropped - 1))) >> kDropped
                                                                                   << kDropped;
  const std::optional<std::uint32_t> centre = WordOfRange(std::bit_cast<double>(rounded));
  if (!centre) return std::nullopt;
  for (std::int64_t k = 0; k <= 2 * kRangeWordSearch; ++k) {
    const std::int64_t word = std::int64_t{*centre} + (k % 2 ? 1 : -1) * ((k + 1) / 2);
    if (word < 0 || word > std::int64_t{UINT32_MAX}) continue;
    if (Rebuilds(d, static_cast<std::uint32_t>(word), p)) return static_cast<std::uint32_t>(word);
  }
  return std::nullopt;
}

[[noreturn]] void FailPackets(const fs::path& file, const std::string& what) {
  throw InputError(file.string() + ": " + what);
}

[[noreturn]] void FailPacketField(const fs::path& file, const std::string& field,
                                  const std::string& what) {
  FailPackets(file, "field '" + field + "': " + what);
}

}  // namespace

std::optional<std::vector<std::uint8_t>> EncodeLidarPackets(const std::vector<LidarPoint>& points,
                                                            const LidarBeamModel& beams) {
  const std::vector<std::uint8_t> section = lidar_packets::BeamSectionOf(beams);
  if (section.empty() || points.size() > UINT32_MAX) return std::nullopt;
  const BeamTable& table = lidar_packets::BeamTableOf(section, "(beam model)");
  const int channels = table.channels;
  const std::size_t columns = static_cast<std::size_t>(table.columns);
  const std::size_t mask_bytes = MaskBytes(channels);
  std::vector<std::uint8_t> masks(columns * mask_bytes, 0);
  std::vector<std::uint32_t> words(points.size(), 0);
  std::vector<std::uint32_t> raw;  // indices of the points kept as raw floats
  bool whole_intensities = true;
  std::size_t c = 0;
  int last_ring = -1;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const LidarPoint& p = points[k];
    if (FloatBits(p.t) != FloatBits(table.t_s[c]) || p.ring <= last_ring) {
      do {
        ++c;
      } while (c < columns && FloatBits(table.t_s[c]) != FloatBits(p.t));
      if (c == columns) return std::nullopt;  // not in column order, or a t of no column
      last_ring = -1;
    }
    if (p.ring >= channels) return std::nullopt;
    last_ring = p.ring;
    masks[c * mask_bytes + p.ring / 8] |= static_cast<std::uint8_t>(1u << (p.ring % 8));
    const Vec3& d = table.directions[c * static_cast<std::size_t>(channels) + p.ring];
    if (const std::optional<std::uint32_t> word = RangeWordOf(d, p)) {
      words[k] = *word;
    } else {
      raw.push_back(static_cast<std::uint32_t>(k));
    }
    whole_intensities = whole_intensities && IsWholeByte(p.intensity);
  }

  const std::size_t n = points.size();
  const std::size_t intensity_bytes = whole_intensities ? 1 : 4;
  const std::size_t body = lidar_packets::kElevationsBegin + 8 * static_cast<std::size_t>(channels);
  std::vector<std::uint8_t> out(body + masks.size() + 4 * n + intensity_bytes * n +
                                kRawPointBytes * raw.size());
  std::memcpy(out.data(), kPacketMagic, sizeof(kPacketMagic));
  PutLittleEndian(&out[8], kPacketVersion);
  PutLittleEndian(&out[kPointsAt], static_cast<std::uint32_t>(n));
  PutLittleEndian(&out[kRawPointsAt], static_cast<std::uint32_t>(raw.size()));
  out[kIntensityEncodingAt] = whole_intensities ? 0 : 1;
  std::memcpy(&out[lidar_packets::kBeamSectionBegin], section.data(), section.size());
  std::uint8_t* at = out.data() + body;
  std::memcpy(at, masks.data(), masks.size());
  at += masks.size();
  for (const std::uint32_t w : words) at = (PutLittleEndian(at, w), at + 4);
  for (const LidarPoint& p : points) {
    if (whole_intensities) {
      *at++ = static_cast<std::uint8_t>(p.intensity);
    } else {
      PutLittleEndian(at, FloatBits(p.intensity));
      at += 4;
    }
  }
  for (const std::uint32_t k : raw) {
    PutLittleEndian(at, k);
    PutLittleEndian(at + 4, FloatBits(points[k].x));
    PutLittleEndian(at + 8, FloatBits(points[k].y));
    PutLittleEndian(at + 12, FloatBits(points[k].z));
    at += kRawPointBytes;
  }
  return out;
}

std::vector<LidarPoint> DecodeLidarPackets(std::span<const std::uint8_t> bytes,
                                           const fs::path& file) {
  const std::size_t size = bytes.size();
  const std::uint8_t* in = bytes.data();
  if (size >= sizeof(kPacketMagic) && std::memcmp(in, kPacketMagic, sizeof(kPacketMagic)) != 0) {
    FailPackets(file, "not a StateBench lidar packets file (its first bytes are not \"SBLIDPK\")");
  }
  if (size < lidar_packets::kElevationsBegin) {
    FailPackets(file, "truncated: " + std::to_string(size) + " bytes, the header alone takes " +
                          std::to_string(lidar_packets::kElevationsBegin) + " or more");
  }
  if (const auto version = GetLittleEndian<std::uint32_t>(in + 8); version != kPacketVersion) {
    FailPacketField(file, "version", std::to_string(version) + ", this reader knows " +
                                         std::to_string(kPacketVersion));
  }
  const std::size_t channels = GetLittleEndian<std::uint16_t>(in + kChannelsAt);
  const std::size_t header = lidar_packets::kBeamSectionBegin + BeamSectionBytes(channels);
  if (size < header) {
    FailPackets(file, "truncated: " + std::to_string(size) + " bytes, the header of " +
                          std::to_string(channels) + " channels takes " + std::to_string(header));
  }
  const std::uint64_t columns = GetLittleEndian<std::uint32_t>(in + kColumnsAt);
  lidar_packets::CheckBeamCounts(channels, columns, file);  // before sizes are computed from them
  const std::uint64_t n = GetLittleEndian<std::uint32_t>(in + kPointsAt);
  const std::uint64_t raw = GetLittleEndian<std::uint32_t>(in + kRawPointsAt);
  const std::uint8_t encoding = in[kIntensityEncodingAt];
  if (encoding > 1) {
    FailPacketField(file, "intensity encoding", std::to_string(encoding) + ", expected 0 or 1");
  }
  const std::size_t mask_bytes = MaskBytes(static_cast<int>(channels));
  const std::uint64_t intensity_bytes = encoding == 0 ? 1 : 4;
  const std::uint64_t expected =
      header + columns * mask_bytes + (4 + intensity_bytes) * n + kRawPointBytes * raw;
  if (size != expected) {
    FailPackets(file, std::string(size < expected ? "truncated" : "too long") + ": " +
                          std::to_string(size) + " bytes, its header announces " +
                          std::to_string(n) + " returns and " + std::to_string(raw) +
                          " raw points (" + std::to_string(expected) + " bytes)");
  }
  const BeamTable& table = lidar_packets::BeamTableOf(
      bytes.subspan(lidar_packets::kBeamSectionBegin, BeamSectionBytes(channels)), file);
  // The masks decide where each point goes: check them before trusting them.
  const std::uint8_t* masks = in + header;
  const unsigned spare_bits = table.channels % 8 ? 0xFFu << (table.channels % 8) & 0xFFu : 0u;
  std::uint64_t hits = 0;
  for (std::uint64_t c = 0; c < columns; ++c) {
    const std::uint8_t* mask = masks + c * mask_bytes;
    for (std::size_t j = 0; j < mask_bytes; ++j) hits += std::popcount(unsigned{mask[j]});
    if (mask[mask_bytes - 1] & spare_bits) {
      FailPacketField(file, "hit masks", "column " + std::to_string(c) +
                                             " has a return of a ring beyond its " +
                                             std::to_string(table.channels) + " channels");
    }
  }
  if (hits != n) {
    FailPacketField(file, "hit masks", std::to_string(hits) + " returns, the header announces " +
                                           std::to_string(n));
  }

  const std::uint8_t* words = masks + columns * mask_bytes;
  const std::uint8_t* intensities = words + 4 * n;
  std::vector<LidarPoint> points(static_cast<std::size_t>(n));
  LidarPoint* out = points.data();
  const std::size_t stride = static_cast<std::size_t>(table.channels);
  for (std::size_t c = 0; c < columns; ++c) {
    const float t = table.t_s[c];
    const Vec3* directions = table.directions.data() + c * stride;
    const std::uint8_t* mask = masks + c * mask_bytes;
    for (std::size_t j = 0; j < mask_bytes; ++j) {
      for (unsigned bits = mask[j]; bits != 0; bits &= bits - 1) {
        const auto ring = static_cast<std::uint16_t>(8 * j + std::countr_zero(bits));
        const float intensity =
            encoding == 0 ? static_cast<float>(*intensities)
                          : std::bit_cast<float>(GetLittleEndian<std::uint32_t>(intensities));
        *out++ = BeamReturn(directions[ring], RangeFromWord(GetLittleEndian<std::uint32_t>(words)),
                            intensity, t, ring);
        words += 4;
        intensities += intensity_bytes;
      }
    }
  }
  const std::uint8_t* at = in + expected - kRawPointBytes * raw;
  std::int64_t last = -1;
  for (std::uint64_t i = 0; i < raw; ++i, at += kRawPointBytes) {
    const std::uint32_t k = GetLittleEndian<std::uint32_t>(at);
    if (k >= n || std::int64_t{k} <= last) {
      FailPacketField(file, "raw points", "raw point " + std::to_string(i) + " names point " +
                                              std::to_string(k) + " (after point " +
                                              std::to_string(last) + ", " + std::to_string(n) +
                                              " points)");
    }
    last = k;
    points[k].x = std::bit_cast<float>(GetLittleEndian<std::uint32_t>(at + 4));
    points[k].y = std::bit_cast<float>(GetLittleEndian<std::uint32_t>(at + 8));
    points[k].z = std::bit_cast<float>(GetLittleEndian<std::uint32_t>(at + 12));
  }
  return points;
}

bool WriteLidarPacketFile(const fs::path& file, const std::vector<LidarPoint>& points,
                          const LidarBeamModel& beams) {
  const std::optional<std::vector<std::uint8_t>> bytes = EncodeLidarPackets(points, beams);
  if (!bytes) return false;
  WriteFileBytes(file, bytes->data(), bytes->size());
  return true;
}

std::vector<LidarPoint> ReadLidarPacketFile(const fs::path& file) {
  thread_local std::vector<std::uint8_t> bytes;
  ReadFileBytes(file, bytes);
  return DecodeLidarPackets(bytes, file);
}

}  // namespace statebench::sensors
