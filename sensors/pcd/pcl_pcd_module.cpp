// libstatebench_pcd.so: PCL's PCD writer and reader behind sensors/pcl_pcd_api.hpp, the only
// code that links PCL's I/O (and with it VTK, OpenNI, Boost, ...).
#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>

#include <cstring>
#include <exception>
#include <fstream>

#include "sensors/pcl_pcd_api.hpp"

namespace statebench::sensors {
namespace {

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

class PclPcdModule final : public PclPcdApi {
 public:
  std::string WriteBinary(const std::string& file,
                          const std::vector<LidarPoint>& points) override {
    try {
      const pcl::PCLPointCloud2 cloud = ToCloud(points);
      pcl::PCDWriter writer;
      if (points.empty()) {
        std::ofstream out(file, std::ios::binary);
        out << writer.generateHeaderBinary(cloud, Eigen::Vector4f::Zero(),
                                           Eigen::Quaternionf::Identity())
            << "DATA binary\n";
        return out ? "" : "cannot write";
      }
      return writer.writeBinary(file, cloud) == 0 ? "" : "cannot write";
    } catch (const std::exception& e) {
      return std::string("cannot write: ") + e.what();
    }
  }

  std::string Read(const std::string& file, PclCloud* out) override {
    try {
      pcl::PCDReader reader;
      pcl::PCLPointCloud2 cloud;
      if (reader.read(file, cloud) != 0) return "PCL cannot read its data";
      out->points = static_cast<std::uint64_t>(cloud.width) * cloud.height;
      out->point_step = cloud.point_step;
      out->data = std::move(cloud.data);
      return "";
    } catch (const std::exception& e) {
      return std::string("PCL cannot read its data: ") + e.what();
    }
  }
};

}  // namespace
}  // namespace statebench::sensors

extern "C" statebench::sensors::PclPcdApi* statebench_pcd_api() {
  static statebench::sensors::PclPcdModule api;
  return &api;
}
