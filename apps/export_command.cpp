// statebench export rosbag LOG --out BAG [--topics-out MAP.yaml] [--time-offset-s S]
//                          [--base-frame F] [--quiet]
//
// A recorded log into a ROS1 bag (sensors/rosbag_export.hpp), and optionally the topic map that
// imports the bag back into the same log.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "core/error.hpp"
#include "sensors/rosbag_export.hpp"

namespace statebench::app {
namespace {

constexpr const char* kUsage =
    "usage: statebench export rosbag LOG --out BAG [--topics-out MAP.yaml] [--time-offset-s S]\n"
    "                                [--base-frame F] [--quiet]\n"
    "  Writes a recorded log (e.g. from statebench record) as a ROS1 bag (docs/real-data.md):\n"
    "  one topic /<sensor id> per stream (sensor_msgs/Imu, NavSatFix, PointCloud2, JointState,\n"
    "  geometry_msgs/TwistStamped, TwistWithCovarianceStamped), the setup's mounts on /tf_static.\n"
    "  --topics-out MAP.yaml  the topic map that imports the bag back (statebench import rosbag)\n"
    "  --time-offset-s S      added to every stamp (ROS1 times are unsigned; default 0)\n"
    "  --base-frame F         parent frame of the mounts (default base_link)\n";

}  // namespace

int RunExport(const std::vector<std::string>& argv) {
  const auto parsed = ParseCommand({"export",
                                    kUsage,
                                    {"quiet"},
                                    {"out", "topics-out", "time-offset-s", "base-frame"},
                                    2,
                                    {"out"}},
                                   argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs* args = &std::get<CliArgs>(parsed);
  try {
    if (args->positional()[0] != "rosbag") {
      throw std::invalid_argument("unknown format '" + args->positional()[0] +
                                  "' (expected: rosbag)");
    }
    const std::filesystem::path log = args->positional()[1];
    const std::filesystem::path bag = *args->Option("out");
    sensors::RosbagExportOptions options;
    options.time_offset_ns = FromSeconds(args->Double("time-offset-s").value_or(0.0));
    options.base_frame = args->Option("base-frame").value_or(options.base_frame);
    if (options.base_frame.empty()) throw std::invalid_argument("--base-frame must not be empty");
    const sensors::RosbagExportResult result = sensors::ExportRosbag(log, bag, options);
    if (!args->Flag("quiet")) {
      std::printf("%s -> %s (%zu static transforms on /tf_static)\n", log.string().c_str(),
                  bag.string().c_str(), result.static_transforms);
      for (const sensors::RosbagExportStream& s : result.streams) {
        const std::string type(sensors::LogStreamTypeName(s.type));
        if (s.topic.empty()) {
          std::printf("  %-16s %-16s not exported (no ROS message type for it)\n", s.id.c_str(),
                      type.c_str());
        } else {
          std::printf("  %-16s %-16s -> %-20s %-42s %8zu\n", s.id.c_str(), type.c_str(),
                      s.topic.c_str(), s.datatype.c_str(), s.count);
        }
      }
    }
    if (const auto map_file = args->Option("topics-out")) {
      const std::string yaml = sensors::RosTopicMapYaml(
          result.topic_map, "# Topic map of " + bag.filename().string() +
                                ", written by statebench export rosbag from " + log.string() +
                                "\n# (docs/real-data.md): statebench import rosbag " +
                                bag.string() + " --topics " + *map_file + " --out LOG\n");
      std::ofstream out(*map_file, std::ios::binary);
      out << yaml;
      if (!out) throw InputError(*map_file + ": cannot write");
    }
    if (result.error) {
      std::fprintf(stderr, "statebench export: %s\n", result.error->c_str());
      std::fprintf(stderr, "statebench export: %s holds what was written before this error\n",
                   bag.string().c_str());
      return 2;
    }
    return 0;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "statebench export: %s\n%s", e.what(), kUsage);
    return 2;
  } catch (...) {
    return ExitCodeForCurrentException("export");
  }
}

}  // namespace statebench::app
