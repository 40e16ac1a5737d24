// The writer of lidar packets files (lidar_packet_file.hpp).
#include <bit>
#include <cmath>
#include <cstring>

#include "sensors/file_bytes.hpp"
#include "sensors/lidar_packet_beams.hpp"
#include "sensors/lidar_packet_file.hpp"
#include "sensors/lidar_range_word.hpp"

namespace statebench::sensors {
namespace {

// How far from the guess (in units of the word's last bit) the encoder looks for a word that
// rebuilds the point: the guess is within a float's rounding (2^-24) of the range, 32 units.
constexpr std::int64_t kRangeWordSearch = 64;

std::uint32_t BitsOf(float v) { return std::bit_cast<std::uint32_t>(v); }

bool IsWholeByte(float v) {
  return v >= 0.f && v <= 255.f && BitsOf(static_cast<float>(static_cast<int>(v))) == BitsOf(v);
}

bool RebuildsPoint(const Vec3& d, std::uint32_t word, const LidarPoint& p) {
  const LidarPoint q = BeamReturn(d, RangeFromWord(word), 0.f, 0.f, 0);
  return BitsOf(q.x) == BitsOf(p.x) && BitsOf(q.y) == BitsOf(p.y) && BitsOf(q.z) == BitsOf(p.z);
}

// A word whose range rebuilds p's x y z on beam d, searched outwards from the range p implies.
std::optional<std::uint32_t> RangeWordOf(const Vec3& d, const LidarPoint& p) {
  const double guess = double{p.x} * d.x() + double{p.y} * d.y() + double{p.z} * d.z();
  if (!(guess > 0.0) || !std::isfinite(guess)) return std::nullopt;
  constexpr int kDropped = 52 - kRangeWordFractionBits;
  const std::uint64_t rounded =
      (std::bit_cast<std::uint64_t>(guess) + (std::uint64_t{1} << (kDropped - 1))) >>
      kDropped << kDropped;
  const std::optional<std::uint32_t> centre = WordOfRange(std::bit_cast<double>(rounded));
  if (!centre) return std::nullopt;
  for (std::int64_t k = 0; k <= 2 * kRangeWordSearch; ++k) {
    const std::int64_t word = std::int64_t{*centre} + (k % 2 ? 1 : -1) * ((k + 1) / 2);
    if (word < 0 || word > std::int64_t{UINT32_MAX}) continue;
    if (RebuildsPoint(d, static_cast<std::uint32_t>(word), p)) {
      return static_cast<std::uint32_t>(word);
    }
  }
  return std::nullopt;
}

// The beam (column * C + ring) of each point, or nullopt unless the points are returns of the
// table's beams in beam order: columns ascending (a point's column is the next one with its t),
// rings ascending within a column, rings below C.
std::optional<std::vector<std::uint32_t>> BeamOfEachPoint(const std::vector<LidarPoint>& points,
                                                          const lidar_packets::BeamTable& table) {
  const auto columns = static_cast<std::size_t>(table.columns);
  std::vector<std::uint32_t> beams(points.size());
  std::size_t c = 0;
  int last_ring = -1;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const LidarPoint& p = points[k];
    if (BitsOf(p.t) != BitsOf(table.t_s[c]) || p.ring <= last_ring) {
      do {
        ++c;
      } while (c < columns && BitsOf(table.t_s[c]) != BitsOf(p.t));
      if (c == columns) return std::nullopt;
      last_ring = -1;
    }
    if (p.ring >= table.channels) return std::nullopt;
    last_ring = p.ring;
    beams[k] = static_cast<std::uint32_t>(c * static_cast<std::size_t>(table.channels) + p.ring);
  }
  return beams;
}

}  // namespace

std::optional<std::vector<std::uint8_t>> EncodeLidarPackets(const std::vector<LidarPoint>& points,
                                                            const LidarBeamModel& beams) {
  const std::vector<std::uint8_t> section = lidar_packets::BeamSectionOf(beams);
  if (section.empty() || points.size() > UINT32_MAX) return std::nullopt;
  const lidar_packets::BeamTable& table = lidar_packets::BeamTableOf(section, "(beam model)");
  const std::optional<std::vector<std::uint32_t>> beam_of = BeamOfEachPoint(points, table);
  if (!beam_of) return std::nullopt;

  // What each point needs: its mask bit, a range word (or a raw point), its intensity.
  const auto channels = static_cast<std::size_t>(table.channels);
  const std::size_t mask_bytes = lidar_packets::MaskBytes(channels);
  std::vector<std::uint8_t> masks(static_cast<std::size_t>(table.columns) * mask_bytes, 0);
  std::vector<std::uint32_t> words(points.size(), 0);
  std::vector<std::uint32_t> raw;  // indices of the points kept as raw floats
  bool whole_intensities = true;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::size_t column = (*beam_of)[k] / channels, ring = (*beam_of)[k] % channels;
    masks[column * mask_bytes + ring / 8] |= static_cast<std::uint8_t>(1u << (ring % 8));
    if (const auto word = RangeWordOf(table.directions[(*beam_of)[k]], points[k])) {
      words[k] = *word;
    } else {
      raw.push_back(static_cast<std::uint32_t>(k));
    }
    whole_intensities = whole_intensities && IsWholeByte(points[k].intensity);
  }

  // The file.
  const std::size_t n = points.size();
  const std::size_t intensity_bytes = whole_intensities ? 1 : 4;
  std::vector<std::uint8_t> out(lidar_packets::HeaderBytes(channels) + masks.size() +
                                lidar_packets::kRangeWordBytes * n + intensity_bytes * n +
                                lidar_packets::kRawPointBytes * raw.size());
  std::memcpy(out.data(), lidar_packets::kMagic, sizeof(lidar_packets::kMagic));
  PutLittleEndian(&out[lidar_packets::kVersionAt], lidar_packets::kVersion);
  PutLittleEndian(&out[lidar_packets::kPointsAt], static_cast<std::uint32_t>(n));
  PutLittleEndian(&out[lidar_packets::kRawPointsAt], static_cast<std::uint32_t>(raw.size()));
  PutLittleEndian(&out[lidar_packets::kChecksumAt], table.checksum);
  out[lidar_packets::kIntensityEncodingAt] =
      whole_intensities ? lidar_packets::kIntensityByte : lidar_packets::kIntensityFloat;
  std::memcpy(&out[lidar_packets::kBeamSectionBegin], section.data(), section.size());
  std::uint8_t* at = out.data() + lidar_packets::HeaderBytes(channels);
  std::memcpy(at, masks.data(), masks.size());
  at += masks.size();
  for (const std::uint32_t w : words) {
    PutLittleEndian(at, w);
    at += lidar_packets::kRangeWordBytes;
  }
  for (const LidarPoint& p : points) {
    if (whole_intensities) {
      *at++ = static_cast<std::uint8_t>(p.intensity);
    } else {
      PutLittleEndian(at, BitsOf(p.intensity));
      at += 4;
    }
  }
  for (const std::uint32_t k : raw) {
    PutLittleEndian(at, k);
    PutLittleEndian(at + 4, BitsOf(points[k].x));
    PutLittleEndian(at + 8, BitsOf(points[k].y));
    PutLittleEndian(at + 12, BitsOf(points[k].z));
    at += lidar_packets::kRawPointBytes;
  }
  return out;
}

bool WriteLidarPacketFile(const std::filesystem::path& file, const std::vector<LidarPoint>& points,
                          const LidarBeamModel& beams) {
  const std::optional<std::vector<std::uint8_t>> bytes = EncodeLidarPackets(points, beams);
  if (!bytes) return false;
  WriteFileBytes(file, bytes->data(), bytes->size());
  return true;
}

}  // namespace statebench::sensors
