#include "sensors/lidar_pcd_io.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>

#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "core/error.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;
using pcl::PCLPointField;

// Packed layout of one point in the file: 5 floats and a uint16, 22 bytes.
constexpr std::uint32_t kPointStep = 5 * sizeof(float) + sizeof(std::uint16_t);

PCLPointField Field(const char* name, std::uint32_t offset, std::uint8_t datatype) {
  PCLPointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = datatype;
  f.count = 1;
  return f;
}

pcl::PCLPointCloud2 ToCloud(const std::vector<LidarPoint>& points) {
  pcl::PCLPointCloud2 cloud;
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(points.size());
  cloud.is_bigendian = false;
  cloud.is_dense = true;
  cloud.point_step = kPointStep;
  cloud.row_step = kPointStep * cloud.width;
  cloud.fields = {
      Field("x", 0, PCLPointField::FLOAT32),  Field("y", 4, PCLPointField::FLOAT32),
      Field("z", 8, PCLPointField::FLOAT32),  Field("intensity", 12, PCLPointField::FLOAT32),
      Field("t", 16, PCLPointField::FLOAT32), Field("ring", 20, PCLPointField::UINT16)};
  cloud.data.resize(static_cast<std::size_t>(cloud.row_step));
  std::uint8_t* out = cloud.data.data();
  for (const LidarPoint& p : points) {
    const float values[5] = {p.x, p.y, p.z, p.intensity, p.t};
    std::memcpy(out, values, sizeof(values));
    std::memcpy(out + sizeof(values), &p.ring, sizeof(p.ring));
    out += kPointStep;
  }
  return cloud;
}

[[noreturn]] void Fail(const fs::path& file, const std::string& what) {
  throw InputError(file.string() + ": " + what);
}

std::optional<std::uint32_t> OffsetOf(const pcl::PCLPointCloud2& cloud, const char* name,
                                      std::uint8_t datatype, const fs::path& file) {
  for (const PCLPointField& f : cloud.fields) {
    if (f.name != name) continue;
    if (f.datatype != datatype || f.count != 1) {
      Fail(file, std::string("field '") + name + "' has type " + std::to_string(f.datatype) +
                     " x " + std::to_string(f.count) + ", expected " +
                     (datatype == PCLPointField::FLOAT32 ? "float32 (F 4)" : "uint16 (U 2)") +
                     " x 1");
    }
    return f.offset;
  }
  return std::nullopt;
}

// What the header of a PCD file announces, read without PCL (which prints its complaints, e.g. on
// an empty cloud): point count, bytes per point, data encoding and where the data starts.
struct PcdLayout {
  std::uintmax_t points = 0;
  std::uintmax_t point_step = 0;
  std::string data;  // ascii | binary | binary_compressed
  std::uintmax_t data_offset = 0;
};

std::optional<PcdLayout> ScanPcdHeader(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  PcdLayout layout;
  std::vector<std::uintmax_t> sizes, counts;
  std::optional<std::uintmax_t> width, height, points;
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    std::uintmax_t v = 0;
    if (key == "SIZE") {
      while (words >> v) sizes.push_back(v);
    } else if (key == "COUNT") {
      while (words >> v) counts.push_back(v);
    } else if (key == "WIDTH" && words >> v) {
      width = v;
    } else if (key == "HEIGHT" && words >> v) {
      height = v;
    } else if (key == "POINTS" && words >> v) {
      points = v;
    } else if (key == "DATA") {
      words >> layout.data;
      const std::streamoff offset = in.tellg();
      if (offset < 0) return std::nullopt;
      layout.data_offset = static_cast<std::uintmax_t>(offset);
      if (counts.empty()) counts.assign(sizes.size(), 1);
      if (sizes.empty() || counts.size() != sizes.size()) return std::nullopt;
      for (std::size_t i = 0; i < sizes.size(); ++i) layout.point_step += sizes[i] * counts[i];
      if (points) {
        layout.points = *points;
      } else if (width && height) {
        layout.points = *width * *height;
      } else {
        return std::nullopt;
      }
      return layout;
    }
  }
  return std::nullopt;
}

}  // namespace

void WriteLidarPcd(const fs::path& file, const std::vector<LidarPoint>& points) {
  const pcl::PCLPointCloud2 cloud = ToCloud(points);
  pcl::PCDWriter writer;
  if (points.empty()) {
    // PCL refuses to write a cloud without data; an empty sweep is its header alone.
    std::ofstream out(file, std::ios::binary);
    out << writer.generateHeaderBinary(cloud, Eigen::Vector4f::Zero(),
                                       Eigen::Quaternionf::Identity())
        << "DATA binary\n";
    if (!out) Fail(file, "cannot write");
    return;
  }
  if (writer.writeBinary(file.string(), cloud) != 0) Fail(file, "cannot write");
}

std::vector<LidarPoint> ReadLidarPcd(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) Fail(file, "no such file");
  const std::optional<PcdLayout> layout = ScanPcdHeader(file);
  if (!layout) Fail(file, "not a PCD file (no complete header up to its DATA line)");
  if (layout->data == "binary") {  // the exact size is known: check it before PCL reads
    const std::uintmax_t expected = layout->data_offset + layout->points * layout->point_step;
    const std::uintmax_t size = fs::file_size(file, ec);
    if (ec || size < expected) {
      Fail(file, "truncated: " + std::to_string(size) + " bytes, the header announces " +
                     std::to_string(layout->points) + " points of " +
                     std::to_string(layout->point_step) + " bytes (" + std::to_string(expected) +
                     " bytes)");
    }
  }
  if (layout->points == 0) return {};
  pcl::PCDReader reader;
  pcl::PCLPointCloud2 cloud;
  if (reader.read(file.string(), cloud) != 0) Fail(file, "PCL cannot read it");
  const std::size_t points = static_cast<std::size_t>(cloud.width) * cloud.height;

  const auto x = OffsetOf(cloud, "x", PCLPointField::FLOAT32, file);
  const auto y = OffsetOf(cloud, "y", PCLPointField::FLOAT32, file);
  const auto z = OffsetOf(cloud, "z", PCLPointField::FLOAT32, file);
  if (!x || !y || !z) Fail(file, "needs the fields x, y and z");
  const auto intensity = OffsetOf(cloud, "intensity", PCLPointField::FLOAT32, file);
  const auto t = OffsetOf(cloud, "t", PCLPointField::FLOAT32, file);
  const auto ring = OffsetOf(cloud, "ring", PCLPointField::UINT16, file);

  std::vector<LidarPoint> out(points);
  if (cloud.data.size() < points * cloud.point_step) Fail(file, "fewer points than announced");
  const std::uint8_t* data = cloud.data.data();
  for (std::size_t i = 0; i < points; ++i, data += cloud.point_step) {
    LidarPoint& p = out[i];
    std::memcpy(&p.x, data + *x, sizeof(float));
    std::memcpy(&p.y, data + *y, sizeof(float));
    std::memcpy(&p.z, data + *z, sizeof(float));
    if (intensity) std::memcpy(&p.intensity, data + *intensity, sizeof(float));
    if (t) std::memcpy(&p.t, data + *t, sizeof(float));
    if (ring) std::memcpy(&p.ring, data + *ring, sizeof(std::uint16_t));
  }
  return out;
}

}  // namespace statebench::sensors
