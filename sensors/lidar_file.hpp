// The files a recorded log may hold one lidar sweep in (docs/log-format.md): a StateBench sweep
// file (`.sweep`, lidar_sweep_file.hpp: the default, about a fifth of a PCD's bytes) or a PCD
// (`.pcd`, lidar_pcd_io.hpp) that PCL and other point-cloud tools open. Both keep every field of
// every point bit for bit. A reader tells them apart by the file name's extension.
#pragma once

#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include "core/measurements.hpp"

namespace statebench::sensors {

enum class LidarFileFormat { kSweep, kPcd };

// "sweep" or "pcd", and back (nullopt for another name).
std::string_view LidarFileFormatName(LidarFileFormat format);
std::optional<LidarFileFormat> ParseLidarFileFormat(std::string_view name);
// ".sweep" or ".pcd".
std::string_view LidarFileExtension(LidarFileFormat format);

// Throws InputError naming the file when it cannot be written.
void WriteLidarFile(const std::filesystem::path& file, const std::vector<LidarPoint>& points,
                    LidarFileFormat format);

// A `.sweep` file as a sweep file, any other as a PCD; throws InputError naming the file.
std::vector<LidarPoint> ReadLidarFile(const std::filesystem::path& file);

}  // namespace statebench::sensors
