#include "sensors/lidar_file.hpp"

#include "sensors/lidar_pcd_io.hpp"
#include "sensors/lidar_sweep_file.hpp"

namespace statebench::sensors {

std::string_view LidarFileFormatName(LidarFileFormat format) {
  return format == LidarFileFormat::kSweep ? "sweep" : "pcd";
}

std::optional<LidarFileFormat> ParseLidarFileFormat(std::string_view name) {
  if (name == "sweep") return LidarFileFormat::kSweep;
  if (name == "pcd") return LidarFileFormat::kPcd;
  return std::nullopt;
}

std::string_view LidarFileExtension(LidarFileFormat format) {
  return format == LidarFileFormat::kSweep ? ".sweep" : ".pcd";
}

void WriteLidarFile(const std::filesystem::path& file, const std::vector<LidarPoint>& points,
                    LidarFileFormat format) {
  if (format == LidarFileFormat::kSweep) {
    WriteLidarSweepFile(file, points);
  } else {
    WriteLidarPcd(file, points);
  }
}

std::vector<LidarPoint> ReadLidarFile(const std::filesystem::path& file) {
  if (file.extension() == LidarFileExtension(LidarFileFormat::kSweep)) {
    return ReadLidarSweepFile(file);
  }
  return ReadLidarPcd(file);
}

}  // namespace statebench::sensors
