#include "sensors/lidar_pcd_io.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>

#include "core/error.hpp"
#include "sensors/pcd_header.hpp"
#include "sensors/pcl_pcd_api.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void Fail(const fs::path& file, const std::string& what) {
  throw InputError(file.string() + ": " + what);
}

// The offset of a field of the expected type in the header's binary layout, nullopt when the
// file has no such field.
std::optional<std::size_t> OffsetOf(const PcdHeader& header, const char* name, char type,
                                    int size, const fs::path& file) {
  const PcdField* f = header.Find(name);
  if (f == nullptr) return std::nullopt;
  if (f->type != type || f->size != size || f->count != 1) {
    Fail(file, std::string("field '") + name + "' is " + f->type + " " + std::to_string(f->size) +
                   " x " + std::to_string(f->count) + ", expected " + type + " " +
                   std::to_string(size) + " x 1");
  }
  return f->offset;
}

// Where each field of a LidarPoint lies in one point of the file's binary layout.
struct PointLayout {
  std::size_t x = 0, y = 0, z = 0;
  std::optional<std::size_t> intensity, t, ring;
};

PointLayout LayoutOf(const PcdHeader& header, const fs::path& file) {
  const auto x = OffsetOf(header, "x", 'F', 4, file);
  const auto y = OffsetOf(header, "y", 'F', 4, file);
  const auto z = OffsetOf(header, "z", 'F', 4, file);
  if (!x || !y || !z) Fail(file, "needs the fields x, y and z");
  return PointLayout{*x,
                     *y,
                     *z,
                     OffsetOf(header, "intensity", 'F', 4, file),
                     OffsetOf(header, "t", 'F', 4, file),
                     OffsetOf(header, "ring", 'U', 2, file)};
}

std::vector<LidarPoint> Unpack(const std::uint8_t* data, std::size_t points,
                               std::size_t point_step, const PointLayout& l) {
  std::vector<LidarPoint> out(points);
  for (std::size_t i = 0; i < points; ++i, data += point_step) {
    LidarPoint& p = out[i];
    std::memcpy(&p.x, data + l.x, sizeof(float));
    std::memcpy(&p.y, data + l.y, sizeof(float));
    std::memcpy(&p.z, data + l.z, sizeof(float));
    if (l.intensity) std::memcpy(&p.intensity, data + *l.intensity, sizeof(float));
    if (l.t) std::memcpy(&p.t, data + *l.t, sizeof(float));
    if (l.ring) std::memcpy(&p.ring, data + *l.ring, sizeof(std::uint16_t));
  }
  return out;
}

// The data of a binary PCD, read directly: the header gave every offset and the exact size.
std::vector<LidarPoint> ReadBinary(const fs::path& file, const PcdHeader& header,
                                   const PointLayout& layout) {
  const std::uint64_t bytes = header.points * header.point_step;
  std::ifstream in(file, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(header.data_offset));
  std::vector<std::uint8_t> data(static_cast<std::size_t>(bytes));
  in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(bytes));
  if (static_cast<std::uint64_t>(in.gcount()) != bytes) Fail(file, "cannot read its data");
  return Unpack(data.data(), static_cast<std::size_t>(header.points), header.point_step, layout);
}

// ascii and binary_compressed data are PCL's to decode, once the header has been accepted.
std::vector<LidarPoint> ReadWithPcl(const fs::path& file, const PcdHeader& header,
                                    const PointLayout& layout) {
  PclCloud cloud;
  if (const std::string why = PclPcd().Read(file.string(), &cloud); !why.empty()) {
    Fail(file, why);
  }
  if (cloud.points != header.points || cloud.point_step != header.point_step ||
      cloud.data.size() < cloud.points * cloud.point_step) {
    Fail(file, "fewer points than announced");
  }
  return Unpack(cloud.data.data(), static_cast<std::size_t>(cloud.points), cloud.point_step,
                layout);
}

}  // namespace

void WriteLidarPcd(const fs::path& file, const std::vector<LidarPoint>& points) {
  if (const std::string why = PclPcd().WriteBinary(file.string(), points); !why.empty()) {
    Fail(file, why);
  }
}

std::vector<LidarPoint> ReadLidarPcd(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) Fail(file, "no such file");
  const PcdHeader header = ReadPcdHeader(file);
  const PointLayout layout = LayoutOf(header, file);
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) Fail(file, "cannot read its size");
  const std::string announced = std::to_string(header.points) + " points of " +
                                std::to_string(header.point_step) + " bytes";
  if (header.data == PcdData::kBinary) {  // the exact size is known: check it before reading
    const std::uint64_t expected = header.data_offset + header.points * header.point_step;
    if (size < expected) {
      Fail(file, "truncated: " + std::to_string(size) + " bytes, the header announces " +
                     announced + " (" + std::to_string(expected) + " bytes)");
    }
  }
  if (header.data == PcdData::kAscii) {
    // Each value takes at least one character and one separator (the last may lack it): a file
    // too short for the announced points is refused before PCL allocates for them.
    std::uint64_t values_per_point = 0;
    for (const PcdField& f : header.fields) values_per_point += static_cast<std::uint64_t>(f.count);
    const std::uint64_t values = header.points * values_per_point;
    if (values > 0 && size < header.data_offset + 2 * values - 1) {
      Fail(file, "truncated: " + std::to_string(size - std::min<std::uintmax_t>(size, header.data_offset)) +
                     " bytes of ascii data cannot hold the header's " + announced);
    }
  }
  if (header.points == 0) return {};
  if (header.data == PcdData::kBinary) return ReadBinary(file, header, layout);
  if (header.data == PcdData::kBinaryCompressed) {
    // Two uint32 (compressed and uncompressed bytes) start the data; check both against the
    // header and the file before PCL decompresses.
    std::uint32_t sizes[2] = {0, 0};
    std::ifstream in(file, std::ios::binary);
    in.seekg(static_cast<std::streamoff>(header.data_offset));
    in.read(reinterpret_cast<char*>(sizes), sizeof(sizes));
    if (!in) Fail(file, "truncated: no compressed data after its header");
    if (sizes[1] != header.points * header.point_step) {
      Fail(file, "its compressed data unpacks to " + std::to_string(sizes[1]) +
                     " bytes, the header announces " + announced);
    }
    if (header.data_offset + sizeof(sizes) + sizes[0] > size) {
      Fail(file, "truncated: " + std::to_string(sizes[0]) + " compressed bytes announced, " +
                     std::to_string(size - header.data_offset - sizeof(sizes)) + " present");
    }
  }
  return ReadWithPcl(file, header, layout);
}

}  // namespace statebench::sensors
