// statebench export rosbag: a recorded log (docs/log-format.md) into a ROS1 bag (Debian's
// rosbag_storage), so that a simulated drive replays in ROS tools. One topic per sensor, named
// "/<sensor id>", frame "<sensor id>", received at the measurement's arrival, stamped with its
// stamp (both plus a time offset); the setup's mounts as /tf_static (base frame -> sensor id,
// latched). docs/real-data.md lists the message of each stream type; dual-antenna headings have
// none and are left out. The topic map it returns imports the bag back into the same log.
//
// No ROS header here: the ROS1 sources of this library compile as C++17 (ros1_messages.hpp).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "sensors/log_format.hpp"
#include "sensors/rosbag_topic_map.hpp"

namespace statebench::sensors {

struct RosbagExportOptions {
  TimeNs time_offset_ns = 0;  // added to every stamp and arrival (ROS1 times are unsigned)
  std::string base_frame = "base_link";
};

struct RosbagExportStream {
  std::string id;
  LogStreamType type = LogStreamType::kImu;
  std::string topic;     // empty: not exported
  std::string datatype;  // "sensor_msgs/Imu"
  std::size_t count = 0;
};

struct RosbagExportResult {
  std::vector<RosbagExportStream> streams;  // in order of first appearance
  std::size_t static_transforms = 0;        // on /tf_static
  RosTopicMap topic_map;                    // imports the bag back
  // Set when the export stopped early (a bad stream file of the log, a stamp ROS1 cannot
  // hold); the bag is closed and holds what was written before.
  std::optional<std::string> error;
};

// Throws InputError, before writing anything, when the log cannot be opened or its setup read,
// or `bag` already exists.
RosbagExportResult ExportRosbag(const std::filesystem::path& log_dir,
                                const std::filesystem::path& bag,
                                const RosbagExportOptions& options = {});

}  // namespace statebench::sensors
