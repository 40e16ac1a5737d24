// statebench import rosbag: a ROS1 bag (read with Debian's rosbag_storage) into a recorded log
// (docs/log-format.md), as a topic map (rosbag_topic_map.hpp) says; docs/real-data.md lists what
// each message field becomes. Stamps: a message's header stamp is the measurement stamp, its
// receive time in the bag the arrival (never before the stamp). Mounts: the static transforms of
// /tf_static and of the map, from the map's base frame to each topic's frame, into setup.yaml,
// with each sensor's latency_s the largest receive - stamp delay seen (for a lidar sweep, after
// its last point) unless the map gives it.
//
// No ROS header here: the ROS1 sources of this library compile as C++17 (ros1_messages.hpp).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "sensors/rosbag_topic_map.hpp"

namespace statebench::sensors {

struct RosbagTopicInfo {
  std::string topic;
  std::string datatype;  // "sensor_msgs/Imu"
  std::size_t messages = 0;
  std::string frame_id;  // of its first message, for the types the import reads ("" otherwise)
  double rate_hz = 0.0;  // from the receive times
};

struct RosbagSummary {
  std::string bag;
  TimeNs begin_ns = 0;  // receive times of the first and last message
  TimeNs end_ns = 0;
  std::vector<RosbagTopicInfo> topics;                // in topic name order
  std::vector<RosStaticTransform> static_transforms;  // of /tf_static
};

// Throws InputError when the file is not a readable ROS1 bag.
RosbagSummary SummarizeRosbag(const std::filesystem::path& bag);

// A topic map (YAML) for the bag's topics of the types the import reads, each choice commented,
// and the other topics listed as comments.
std::string SuggestTopicMap(const RosbagSummary& summary);

// Whether the import turns messages of `datatype` into sensors of `kind`.
bool RosbagImportAccepts(RosTopicKind kind, const std::string& datatype);

// Checks a topic map against the bag's topics (topic -> datatype) before anything is written:
// InputError naming the map's line for a topic the bag lacks, a type the entry cannot take, or
// a TwistStamped body velocity without twist_sigma.
void CheckTopicMap(const RosTopicMap& map, const std::map<std::string, std::string>& datatypes,
                   const std::filesystem::path& bag);

struct RosbagImportOptions {
  TimeNs time_offset_ns = 0;  // added to every stamp and arrival
};

struct RosbagImportStream {
  std::string topic;
  std::string datatype;
  std::string id;
  RosTopicKind kind = RosTopicKind::kImu;
  std::string frame_id;   // the messages' (or the map's), whose mount went into setup.yaml
  std::size_t count = 0;  // measurements written
  // Messages or points left out: NO_FIX messages without a position, JointStates naming none of
  // the entry's joints, non-finite lidar points.
  std::size_t skipped = 0;
  std::size_t lidar_points = 0;
  std::size_t arrivals_at_stamp = 0;  // received before their stamp: arrival set to the stamp
  TimeNs first_stamp_ns = 0;
  TimeNs last_stamp_ns = 0;
  std::optional<double> latency_s;  // written to setup.yaml
  std::string time_field;           // lidar: the per-point time field used ("" = none)
};

struct RosbagImportResult {
  std::vector<RosbagImportStream> streams;  // in the map's order
  std::vector<RosbagTopicInfo> unmapped;    // topics of the bag the map does not name
  std::vector<std::string> notes;           // e.g. a topic without frame, mounted at the base frame
  // Set when the import stopped early: "BAG: topic '/imu' message 12 (...): what". The log then
  // holds every measurement converted before (manifest and setup written).
  std::optional<std::string> error;
};

// Throws InputError, before anything is written, when the bag cannot be read, the map names a
// topic that is not in the bag or a type its messages cannot become, or out_dir holds a log.
RosbagImportResult ImportRosbag(const std::filesystem::path& bag, const RosTopicMap& map,
                                const std::filesystem::path& out_dir,
                                const RosbagImportOptions& options = {});

}  // namespace statebench::sensors
