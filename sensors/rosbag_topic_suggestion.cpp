// The topic map suggested for a bag (statebench import rosbag BAG without --topics).
#include <cstdio>
#include <set>

#include "sensors/rosbag_import.hpp"

namespace statebench::sensors {
namespace {

std::optional<RosTopicKind> SuggestedKind(const std::string& datatype) {
  if (datatype == "sensor_msgs/Imu") return RosTopicKind::kImu;
  if (datatype == "sensor_msgs/NavSatFix") return RosTopicKind::kGnss;
  if (datatype == "sensor_msgs/PointCloud2") return RosTopicKind::kLidar;
  if (datatype == "sensor_msgs/JointState") return RosTopicKind::kWheelEncoders;
  if (RosbagImportAccepts(RosTopicKind::kBodyVelocity, datatype)) {
    return RosTopicKind::kBodyVelocity;
  }
  return std::nullopt;
}

// "/imu/data" -> "imu_data", unique among `taken`.
std::string SensorIdFor(const std::string& topic, std::set<std::string>* taken) {
  std::string id;
  for (const char c : topic) {
    if (c == '/' || c == '\\') {
      if (!id.empty() && id.back() != '_') id += '_';
    } else {
      id += c;
    }
  }
  while (!id.empty() && id.back() == '_') id.pop_back();
  if (id.empty() || id == "." || id == "..") id = "sensor";
  std::string unique = id;
  for (int n = 2; taken->count(unique) > 0; ++n) unique = id + "_" + std::to_string(n);
  taken->insert(unique);
  return unique;
}

std::string Describe(const RosbagTopicInfo& t) {
  char rate[32];
  std::snprintf(rate, sizeof(rate), "%.1f Hz", t.rate_hz);
  std::string out = t.datatype + ", " + std::to_string(t.messages) + " messages, " + rate;
  if (!t.frame_id.empty()) {
    out += (t.datatype == "nav_msgs/Odometry" ? ", child frame '" : ", frame '") + t.frame_id + "'";
  }
  return out;
}

}  // namespace

std::string SuggestTopicMap(const RosbagSummary& summary) {
  std::string y =
      "# Topic map suggested by statebench import rosbag for " + summary.bag +
      "\n# (docs/real-data.md). Check every entry: ids name the log's files and the sensors of its"
      "\n# setup.yaml; each topic's mount is the static transform from base_frame to its frame.\n";
  y += "base_frame: base_link\n";
  if (summary.static_transforms.empty()) {
    y += "# The bag has no /tf_static: give each topic's T_body_sensor, or static_transforms.\n";
  } else {
    y += "# /tf_static of the bag:";
    for (const RosStaticTransform& s : summary.static_transforms) {
      y += " " + s.parent + " -> " + s.child + ";";
    }
    y += "\n";
  }
  y +=
      "# origin: {latitude_deg: 0.0, longitude_deg: 0.0, altitude_m: 0.0}  # WGS84 anchor of ENU\n";
  y += "topics:\n";
  std::set<std::string> taken;
  std::string others;
  for (const RosbagTopicInfo& t : summary.topics) {
    const std::optional<RosTopicKind> kind = SuggestedKind(t.datatype);
    if (!kind || t.messages == 0) {
      if (t.topic != "/tf_static") others += "#   " + t.topic + " (" + Describe(t) + ")\n";
      continue;
    }
    const std::string id = SensorIdFor(t.topic, &taken);
    const bool joints = *kind == RosTopicKind::kWheelEncoders;
    const std::string c = joints ? "  # " : "  ";  // joint names cannot be guessed: commented
    y += c + "- topic: \"" + t.topic + "\"  # " + Describe(t) + "\n";
    y += c + "  id: \"" + id + "\"\n";
    y += c + "  type: " + std::string(RosTopicKindName(*kind));
    if (*kind == RosTopicKind::kBodyVelocity) {
      y += "  # or speed_encoder (twist.linear.x only)";
    }
    y += "\n";
    if (*kind == RosTopicKind::kGnss) {
      y += "    # position_sigma_m: [1.0, 1.0, 2.0]  # needed when position_covariance_type is 0\n";
    }
    if (t.datatype == "geometry_msgs/TwistStamped") {
      y += "    twist_sigma: [0.1, 0.1, 0.1, 0.1, 0.1, 0.1]  # no covariance in the messages: "
           "set your odometry's sigmas (m/s, rad/s)\n";
    }
    if (joints) {
      y +=
          "  #   joints: [\"front_left\", \"front_right\", \"rear_left\", \"rear_right\"]  # wheel "
          "joints; or type: steering_encoder, joint: NAME\n";
    }
  }
  if (!others.empty()) y += "# Not imported (no conversion for these types):\n" + others;
  return y;
}

}  // namespace statebench::sensors
