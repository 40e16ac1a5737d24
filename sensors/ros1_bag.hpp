// What the bag import and the bag summary share: opening a bag with InputError instead of
// rosbag's exceptions, bag times as text, /tf_static transforms. PRIVATE to the ROS1 sources of
// sensors/ (C++17, like ros1_messages.hpp).
#pragma once

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "sensors/rosbag_topic_map.hpp"

namespace statebench::sensors::ros1 {

inline constexpr const char* kTfStaticTopic = "/tf_static";

inline std::unique_ptr<rosbag::Bag> OpenBagForReading(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string() + ": no such bag file");
  }
  auto bag = std::make_unique<rosbag::Bag>();
  try {
    bag->open(path.string(), rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw InputError(path.string() + ": not a readable ROS1 bag: " + e.what() +
                     " (a recording cut short has no index: `rosbag reindex` repairs it)");
  }
  return bag;
}

// "1700000000.012345678 s"
inline std::string BagTimeText(const ros::Time& t) {
  char text[40];
  std::snprintf(text, sizeof(text), "%u.%09u s", t.sec, t.nsec);
  return text;
}

inline bool IsTfMessage(const std::string& datatype) {
  return datatype == "tf2_msgs/TFMessage" || datatype == "tf/tfMessage";  // same layout and md5
}

// The frame the import mounts a message's sensor at: its header frame (an Odometry's child
// frame), normalised; "" for types the import does not read or a message that does not decode.
// Defined in rosbag_import.cpp.
std::string FrameOfMessage(const rosbag::MessageInstance& m);

// The transforms of a /tf_static message; throws InputError on a non-finite value or a
// quaternion that is not of unit norm.
inline std::vector<RosStaticTransform> StaticTransformsOf(const rosbag::MessageInstance& m) {
  const auto msg = m.instantiate<tf2_msgs::TFMessage>();
  if (!msg) throw InputError("message does not match the definition of tf2_msgs/TFMessage");
  std::vector<RosStaticTransform> out;
  for (const geometry_msgs::TransformStamped& ts : msg->transforms) {
    const auto& t = ts.transform.translation;
    const auto& r = ts.transform.rotation;
    const Quat q(r.w, r.x, r.y, r.z);
    if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z) ||
        !std::isfinite(q.norm()) || std::abs(q.norm() - 1.0) > 1e-3) {
      throw InputError("transform '" + ts.header.frame_id + "' -> '" + ts.child_frame_id +
                       "' is not finite or its quaternion is not of unit norm");
    }
    RosStaticTransform s;
    s.parent = NormalizedFrameId(ts.header.frame_id);
    s.child = NormalizedFrameId(ts.child_frame_id);
    s.T_parent_child = SE3(q, Vec3(t.x, t.y, t.z));
    s.where = std::string(kTfStaticTopic);
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace statebench::sensors::ros1
