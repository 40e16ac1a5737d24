// The files a recorded log may hold one lidar sweep in (docs/log-format.md): a StateBench lidar
// packets file (`.packets`, lidar_packet_file.hpp: the beam model in its header, a range and an
// intensity byte per return; a quarter of a PCD's bytes, read faster than a PCD), a StateBench
// sweep file (`.sweep`, lidar_sweep_file.hpp: any points, compressed, a fifth of a PCD's bytes)
// or a PCD (`.pcd`, lidar_pcd_io.hpp) that PCL and other point-cloud tools open. All keep every
// field of every point bit for bit. A reader tells them apart by the file name's extension.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/measurements.hpp"
#include "sensors/lidar_beam_model.hpp"

namespace statebench::sensors {

enum class LidarFileFormat { kPackets, kSweep, kPcd };

// "packets", "sweep" or "pcd", and back (nullopt for another name).
std::string_view LidarFileFormatName(LidarFileFormat format);
std::optional<LidarFileFormat> ParseLidarFileFormat(std::string_view name);
// ".packets", ".sweep" or ".pcd".
std::string_view LidarFileExtension(LidarFileFormat format);

// Writes one sweep as dir/<stem><extension of the format used> and returns that file name. The
// packets format needs the lidar's beam model (`beams`) and points that are its returns in beam
// order (EncodeLidarPackets); a sweep that is not (no model given, or a fault reordered or retimed
// its points) is written as a sweep file instead. Throws InputError naming the file when it
// cannot be written.
std::string WriteLidarFile(const std::filesystem::path& dir, std::string_view stem,
                           const std::vector<LidarPoint>& points, LidarFileFormat format,
                           const LidarBeamModel* beams = nullptr);

// By the name's extension: `.packets`, `.sweep`, any other a PCD; throws InputError naming the
// file.
std::vector<LidarPoint> ReadLidarFile(const std::filesystem::path& file);

}  // namespace statebench::sensors
