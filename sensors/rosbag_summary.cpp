// What a bag holds, for `statebench import rosbag BAG` without a topic map (compiled as C++17:
// ros1_bag.hpp). The messages are decoded in rosbag_import.cpp (FrameOfMessage), so that their
// templates are instantiated once.
#include <map>

#include "sensors/ros1_bag.hpp"
#include "sensors/rosbag_import.hpp"

#include "core/error.hpp"

namespace statebench::sensors {
bool RosbagImportAccepts(RosTopicKind kind, const std::string& datatype) {
  switch (kind) {
    case RosTopicKind::kImu:
      return datatype == "sensor_msgs/Imu";
    case RosTopicKind::kGnss:
      return datatype == "sensor_msgs/NavSatFix";
    case RosTopicKind::kBodyVelocity:
    case RosTopicKind::kSpeedEncoder:
      return datatype == "nav_msgs/Odometry" || datatype == "geometry_msgs/TwistStamped" ||
             datatype == "geometry_msgs/TwistWithCovarianceStamped";
    case RosTopicKind::kGnssVelocity:
      return datatype == "geometry_msgs/TwistStamped" ||
             datatype == "geometry_msgs/TwistWithCovarianceStamped";
    case RosTopicKind::kSteeringEncoder:
    case RosTopicKind::kWheelEncoders:
      return datatype == "sensor_msgs/JointState";
    case RosTopicKind::kLidar:
      return datatype == "sensor_msgs/PointCloud2";
  }
  return false;
}

RosbagSummary SummarizeRosbag(const std::filesystem::path& path) {
  const std::unique_ptr<rosbag::Bag> bag = ros1::OpenBagForReading(path);
  RosbagSummary summary;
  summary.bag = path.string();
  try {
    std::map<std::string, std::string> datatypes;
    rosbag::View all(*bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) datatypes[c->topic] = c->datatype;
    if (all.size() > 0) {
      summary.begin_ns = static_cast<TimeNs>(all.getBeginTime().toNSec());
      summary.end_ns = static_cast<TimeNs>(all.getEndTime().toNSec());
    }
    for (const auto& [topic, datatype] : datatypes) {
      RosbagTopicInfo info{topic, datatype, 0, "", 0.0};
      rosbag::View view(*bag, rosbag::TopicQuery(topic));
      info.messages = view.size();
      const double span_s = (view.getEndTime() - view.getBeginTime()).toSec();
      if (info.messages > 1 && span_s > 0.0) {
        info.rate_hz = static_cast<double>(info.messages - 1) / span_s;
      }
      for (const rosbag::MessageInstance& m : view) {
        info.frame_id = ros1::FrameOfMessage(m);
        break;
      }
      if (topic == ros1::kTfStaticTopic && ros1::IsTfMessage(datatype)) {
        for (const rosbag::MessageInstance& m : view) {
          try {
            for (RosStaticTransform& s : ros1::StaticTransformsOf(m)) {
              summary.static_transforms.push_back(std::move(s));
            }
          } catch (const InputError& e) {
            throw InputError(std::string("topic '") + ros1::kTfStaticTopic + "': " + e.what());
          }
        }
      }
      summary.topics.push_back(std::move(info));
    }
  } catch (const std::exception& e) {  // rosbag::BagException, InputError
    throw InputError(path.string() + ": " + e.what());
  }
  return summary;
}

void CheckTopicMap(const RosTopicMap& map, const std::map<std::string, std::string>& datatypes,
                   const std::filesystem::path& bag) {
  for (const RosTopicEntry& e : map.topics) {
    const auto it = datatypes.find(e.topic);
    if (it == datatypes.end()) {
      std::string topics;
      for (const auto& [t, d] : datatypes) topics += (topics.empty() ? "" : ", ") + t;
      throw InputError(e.where + ": topic '" + e.topic + "' is not in " + bag.string() +
                       " (its topics: " + topics + ")");
    }
    if (!RosbagImportAccepts(e.kind, it->second)) {
      throw InputError(e.where + ": topic '" + e.topic + "' holds " + it->second +
                       " messages, which cannot become a sensor of type '" +
                       std::string(RosTopicKindName(e.kind)) + "'");
    }
    if (e.kind == RosTopicKind::kBodyVelocity && it->second == "geometry_msgs/TwistStamped" &&
        !e.twist_sigma) {
      throw InputError(e.where + ": topic '" + e.topic +
                       "' (geometry_msgs/TwistStamped) carries no covariance: give twist_sigma "
                       "[vx, vy, vz, wx, wy, wz] (m/s, rad/s)");
    }
  }
}

}  // namespace statebench::sensors
