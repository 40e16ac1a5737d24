#include "sensors/lidar_packet_beams.hpp"

#include <bit>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "sensors/file_bytes.hpp"

namespace statebench::sensors::lidar_packets {
namespace {

// Offsets inside the beam section (file offsets - kBeamSectionBegin, lidar_packet_layout.hpp).
constexpr std::size_t kSectionClockwise = 0, kSectionChannels = kChannelsAt - kBeamSectionBegin,
                      kSectionColumns = kColumnsAt - kBeamSectionBegin,
                      kSectionRate = kSectionColumns + 4, kSectionAzimuth = kSectionRate + 8,
                      kSectionElevations = kElevationsBegin - kBeamSectionBegin;
static_assert(kSectionAzimuth + 8 == kSectionElevations);

double GetDouble(const std::uint8_t* in) {
  return std::bit_cast<double>(GetLittleEndian<std::uint64_t>(in));
}

void PutDouble(std::uint8_t* out, double v) {
  PutLittleEndian(out, std::bit_cast<std::uint64_t>(v));
}

bool BeamModelFits(const LidarBeamModel& b) {
  if (b.channels() < 1 || b.channels() > kMaxChannels || b.columns < 1 || b.columns > kMaxColumns ||
      static_cast<std::int64_t>(b.channels()) * b.columns > kMaxBeams) {
    return false;
  }
  if (!std::isfinite(b.rotation_rate_hz) || !(b.rotation_rate_hz > 0.0) || b.PeriodNs() < 1 ||
      !std::isfinite(b.azimuth_start_rad)) {
    return false;
  }
  for (const double e : b.elevations_rad) {
    if (!std::isfinite(e)) return false;
  }
  return true;
}

[[noreturn]] void FailBeams(const std::filesystem::path& file, const std::string& field,
                            const std::string& what) {
  throw InputError(file.string() + ": field '" + field + "': " + what);
}

LidarBeamModel ParseBeamSection(std::span<const std::uint8_t> s,
                                const std::filesystem::path& file) {
  LidarBeamModel b;
  if (s[kSectionClockwise] > 1) {
    FailBeams(file, "clockwise", std::to_string(s[kSectionClockwise]) + ", expected 0 or 1");
  }
  b.clockwise = s[kSectionClockwise] == 1;
  const int channels = GetLittleEndian<std::uint16_t>(&s[kSectionChannels]);
  const std::uint32_t columns = GetLittleEndian<std::uint32_t>(&s[kSectionColumns]);
  CheckBeamCounts(static_cast<std::uint64_t>(channels), columns, file);
  b.columns = static_cast<int>(columns);
  b.rotation_rate_hz = GetDouble(&s[kSectionRate]);
  if (!std::isfinite(b.rotation_rate_hz) || !(b.rotation_rate_hz > 0.0) || b.PeriodNs() < 1) {
    FailBeams(file, "rotation rate", "not a positive rate with a period of 1 ns or more");
  }
  b.azimuth_start_rad = GetDouble(&s[kSectionAzimuth]);
  if (!std::isfinite(b.azimuth_start_rad)) FailBeams(file, "first azimuth", "not finite");
  b.elevations_rad.resize(static_cast<std::size_t>(channels));
  for (int r = 0; r < channels; ++r) {
    b.elevations_rad[r] = GetDouble(&s[kSectionElevations + 8 * static_cast<std::size_t>(r)]);
    if (!std::isfinite(b.elevations_rad[r])) {
      FailBeams(file, "elevations", "ring " + std::to_string(r) + " is not finite");
    }
  }
  return b;
}

}  // namespace

void CheckBeamCounts(std::uint64_t channels, std::uint64_t columns,
                     const std::filesystem::path& file) {
  if (channels < 1 || channels > kMaxChannels) {
    FailBeams(
        file, "channels",
        std::to_string(channels) + ", a packets file holds 1 to " + std::to_string(kMaxChannels));
  }
  if (columns < 1 || columns > static_cast<std::uint64_t>(kMaxColumns) ||
      channels * columns > static_cast<std::uint64_t>(kMaxBeams)) {
    FailBeams(file, "columns",
              std::to_string(columns) + " of " + std::to_string(channels) +
                  " channels: a packets file holds 1 to " + std::to_string(kMaxColumns) +
                  " columns and at most " + std::to_string(kMaxBeams) + " beams");
  }
}

std::vector<std::uint8_t> BeamSectionOf(const LidarBeamModel& beams) {
  if (!BeamModelFits(beams)) return {};
  const auto channels = static_cast<std::size_t>(beams.channels());
  std::vector<std::uint8_t> s(BeamSectionBytes(channels));
  s[kSectionClockwise] = beams.clockwise ? 1 : 0;
  PutLittleEndian(&s[kSectionChannels], static_cast<std::uint16_t>(channels));
  PutLittleEndian(&s[kSectionColumns], static_cast<std::uint32_t>(beams.columns));
  PutDouble(&s[kSectionRate], beams.rotation_rate_hz);
  PutDouble(&s[kSectionAzimuth], beams.azimuth_start_rad);
  for (std::size_t r = 0; r < channels; ++r)
    PutDouble(&s[kSectionElevations + 8 * r], beams.elevations_rad[r]);
  return s;
}

const BeamTable& BeamTableOf(std::span<const std::uint8_t> section,
                             const std::filesystem::path& file) {
  thread_local std::vector<std::uint8_t> key;
  thread_local BeamTable table;
  if (key.size() == section.size() && std::equal(key.begin(), key.end(), section.begin())) {
    return table;
  }
  const LidarBeamModel beams = ParseBeamSection(section, file);
  key.clear();  // a throwing rebuild leaves no stale key behind
  table.channels = beams.channels();
  table.columns = beams.columns;
  table.directions = beams.Directions();
  table.checksum = 0xcbf29ce484222325ull;  // FNV-1a, 64 bits
  for (const Vec3& d : table.directions) {
    for (int i = 0; i < 3; ++i) {
      const auto bits = std::bit_cast<std::uint64_t>(d[i]);
      for (int b = 0; b < 64; b += 8) {
        table.checksum = (table.checksum ^ ((bits >> b) & 0xFF)) * 0x100000001b3ull;
      }
    }
  }
  table.t_s.resize(static_cast<std::size_t>(beams.columns));
  for (int c = 0; c < beams.columns; ++c) table.t_s[c] = beams.ColumnTimeS(c);
  key.assign(section.begin(), section.end());
  return table;
}

void CheckDirections(const BeamTable& table, std::uint64_t file_checksum,
                     const std::filesystem::path& file) {
  if (table.checksum != file_checksum) {
    FailBeams(file, "direction checksum",
              "the beam directions computed here differ from the writer's (another C library's "
              "cos or sin?): its points cannot be rebuilt bit for bit");
  }
}

}  // namespace statebench::sensors::lidar_packets
