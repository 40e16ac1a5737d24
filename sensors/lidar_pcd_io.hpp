// One lidar sweep as a PCD file (PCL's I/O, binary): fields x y z intensity t (float32, lidar
// frame m, intensity, seconds after the scan stamp) and ring (uint16), one point per return, in
// the order of LidarScan::points. Floats are stored raw, so a read gives the written bits back.
// Binary files are read directly; PCL writes them and decodes ascii and binary_compressed data,
// from a module loaded when first needed (pcl_pcd_api.hpp).
#pragma once

#include <filesystem>
#include <vector>

#include "core/measurements.hpp"

namespace statebench::sensors {

// Throws InputError naming the file when it cannot be written.
void WriteLidarPcd(const std::filesystem::path& file, const std::vector<LidarPoint>& points);

// Reads a PCD file with at least the fields x, y, z (float32); intensity and t (float32) and
// ring (uint16) are read when present (0 otherwise). Throws InputError naming the file when it
// is missing, truncated (fewer bytes than its header announces) or malformed, or a field has
// another type.
std::vector<LidarPoint> ReadLidarPcd(const std::filesystem::path& file);

}  // namespace statebench::sensors
