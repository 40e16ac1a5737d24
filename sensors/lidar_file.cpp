#include "sensors/lidar_file.hpp"

#include <array>

#include "sensors/lidar_packet_file.hpp"
#include "sensors/lidar_pcd_io.hpp"
#include "sensors/lidar_sweep_file.hpp"

namespace statebench::sensors {
namespace {

struct LidarFileFormatNames {
  LidarFileFormat format;
  std::string_view name, extension;
};

constexpr std::array<LidarFileFormatNames, 3> kLidarFileFormats = {{
    {LidarFileFormat::kPackets, "packets", ".packets"},
    {LidarFileFormat::kSweep, "sweep", ".sweep"},
    {LidarFileFormat::kPcd, "pcd", ".pcd"},
}};

const LidarFileFormatNames& NamesOf(LidarFileFormat format) {
  return kLidarFileFormats[static_cast<std::size_t>(format)];
}

}  // namespace

std::string_view LidarFileFormatName(LidarFileFormat format) { return NamesOf(format).name; }

std::optional<LidarFileFormat> ParseLidarFileFormat(std::string_view name) {
  for (const auto& f : kLidarFileFormats) {
    if (f.name == name) return f.format;
  }
  return std::nullopt;
}

std::string_view LidarFileExtension(LidarFileFormat format) { return NamesOf(format).extension; }

std::string WriteLidarFile(const std::filesystem::path& dir, std::string_view stem,
                           const std::vector<LidarPoint>& points, LidarFileFormat format,
                           const LidarBeamModel* beams) {
  std::string name(stem);
  if (format == LidarFileFormat::kPackets) {
    const std::string packets = name + std::string(LidarFileExtension(format));
    if (beams != nullptr && WriteLidarPacketFile(dir / packets, points, *beams)) return packets;
    format = LidarFileFormat::kSweep;
  }
  name += LidarFileExtension(format);
  if (format == LidarFileFormat::kSweep) {
    WriteLidarSweepFile(dir / name, points);
  } else {
    WriteLidarPcd(dir / name, points);
  }
  return name;
}

std::vector<LidarPoint> ReadLidarFile(const std::filesystem::path& file) {
  if (file.extension() == LidarFileExtension(LidarFileFormat::kPackets)) {
    return ReadLidarPacketFile(file);
  }
  if (file.extension() == LidarFileExtension(LidarFileFormat::kSweep)) {
    return ReadLidarSweepFile(file);
  }
  return ReadLidarPcd(file);
}

}  // namespace statebench::sensors
