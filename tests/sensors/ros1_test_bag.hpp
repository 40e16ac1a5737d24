// A ROS1 bag written message by message for the import tests, in a temporary folder (named with
// the process id) with the topic map and the log beside it. Includes ROS1 message headers: only
// for the *_ros1_test.cpp files, compiled as C++17 (tests/CMakeLists.txt).
#pragma once

#include <geometry_msgs/TwistStamped.h>
#include <geometry_msgs/TwistWithCovarianceStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/NavSatFix.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/measurements.hpp"
#include "sensors/log_reader.hpp"

namespace statebench::sensors::testing {

inline ros::Time Ros(TimeNs t_ns) {
  ros::Time t;
  t.fromNSec(static_cast<std::uint64_t>(t_ns));
  return t;
}

inline std_msgs::Header RosHeader(TimeNs stamp_ns, const std::string& frame) {
  std_msgs::Header h;
  h.stamp = Ros(stamp_ns);
  h.frame_id = frame;
  return h;
}

class TestBag {
 public:
  explicit TestBag(const std::string& name)
      : dir_(std::filesystem::temp_directory_path() /
             ("statebench_rosbag_test_" + std::to_string(::getpid()) + "_" + name)) {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    bag_.open(bag().string(), rosbag::bagmode::Write);
  }
  ~TestBag() {
    if (open_) bag_.close();
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  std::filesystem::path bag() const { return dir_ / "test.bag"; }
  std::filesystem::path log() const { return dir_ / "log"; }
  std::filesystem::path map() const { return dir_ / "map.yaml"; }
  const std::filesystem::path& dir() const { return dir_; }

  template <typename Msg>
  void Write(const std::string& topic, TimeNs received_ns, const Msg& msg) {
    bag_.write(topic, Ros(received_ns), msg);
  }
  // One /tf_static message: parent -> child with a translation and a quaternion (w, x, y, z).
  void StaticTransform(const std::string& parent, const std::string& child, const Vec3& t,
                       const Quat& q, TimeNs received_ns = 1) {
    tf2_msgs::TFMessage msg;
    geometry_msgs::TransformStamped ts;
    ts.header = RosHeader(received_ns, parent);
    ts.child_frame_id = child;
    ts.transform.translation.x = t.x();
    ts.transform.translation.y = t.y();
    ts.transform.translation.z = t.z();
    ts.transform.rotation.w = q.w();
    ts.transform.rotation.x = q.x();
    ts.transform.rotation.y = q.y();
    ts.transform.rotation.z = q.z();
    msg.transforms.push_back(ts);
    Write("/tf_static", received_ns, msg);
  }
  void Close() {
    if (open_) bag_.close();
    open_ = false;
  }
  void WriteMap(const std::string& yaml) const { std::ofstream(map()) << yaml; }

 private:
  std::filesystem::path dir_;
  rosbag::Bag bag_;
  bool open_ = true;
};

inline std::vector<Measurement> ReadLog(const std::filesystem::path& dir,
                                        std::optional<std::string>* error = nullptr) {
  LogReader reader(dir);
  std::vector<Measurement> out;
  while (auto m = reader.Next()) out.push_back(std::move(*m));
  if (error != nullptr) *error = reader.error();
  return out;
}

template <typename T>
std::vector<T> OfSensor(const std::vector<Measurement>& all, const std::string& id) {
  std::vector<T> out;
  for (const Measurement& m : all) {
    if (const auto* x = std::get_if<T>(&m); x != nullptr && x->header.sensor_id == id) {
      out.push_back(*x);
    }
  }
  return out;
}

// A PointCloud2 field description.
inline sensor_msgs::PointField Field(const std::string& name, std::uint32_t offset,
                                     std::uint8_t datatype) {
  sensor_msgs::PointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = datatype;
  f.count = 1;
  return f;
}

template <typename T>
void Put(sensor_msgs::PointCloud2* cloud, std::size_t point, std::uint32_t offset, T value) {
  std::memcpy(cloud->data.data() + point * cloud->point_step + offset, &value, sizeof(T));
}

}  // namespace statebench::sensors::testing
