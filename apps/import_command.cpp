// statebench import rosbag BAG [--topics MAP.yaml --out LOG] [--time-offset-s S] [--quiet]
//
// With a topic map: the bag's mapped topics into a recorded log (sensors/rosbag_import.hpp).
// Without one: the bag's topics, types, counts, rates and frames, and a suggested topic map, all
// on stdout as one YAML document (the listing as comments), so `... > MAP.yaml` saves it.
#include <cstdio>
#include <filesystem>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "core/error.hpp"
#include "sensors/rosbag_import.hpp"

namespace statebench::app {
namespace {

constexpr const char* kUsage =
    "usage: statebench import rosbag BAG [--topics MAP.yaml --out LOG] [--time-offset-s S]\n"
    "                                    [--quiet]\n"
    "  Converts a ROS1 bag into a recorded log (docs/real-data.md): the topics MAP.yaml names\n"
    "  (sensor_msgs/Imu, NavSatFix, PointCloud2, JointState, nav_msgs/Odometry,\n"
    "  geometry_msgs/TwistStamped, TwistWithCovarianceStamped), with /tf_static as the mounts of\n"
    "  the log's setup.yaml. Without --topics: lists the bag's topics and prints a suggested\n"
    "  MAP.yaml on stdout.\n"
    "  --time-offset-s S  added to every stamp (e.g. minus the bag's start time)\n";

std::string Seconds(TimeNs t_ns) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.3f", ToSeconds(t_ns));
  return text;
}

int ListTopics(const std::filesystem::path& bag) {
  const sensors::RosbagSummary summary = sensors::SummarizeRosbag(bag);
  std::printf("# %s: %zu topics, receive times %s .. %s s (%s s)\n", bag.string().c_str(),
              summary.topics.size(), Seconds(summary.begin_ns).c_str(),
              Seconds(summary.end_ns).c_str(), Seconds(summary.end_ns - summary.begin_ns).c_str());
  std::printf("#   %-28s %-42s %9s %10s  %s\n", "topic", "type", "messages", "rate", "frame");
  for (const sensors::RosbagTopicInfo& t : summary.topics) {
    std::printf("#   %-28s %-42s %9zu %7.1f Hz  %s\n", t.topic.c_str(), t.datatype.c_str(),
                t.messages, t.rate_hz, t.frame_id.c_str());
  }
  std::printf(
      "#\n# Save this as MAP.yaml, check it, then:\n"
      "#   statebench import rosbag %s --topics MAP.yaml --out LOG\n",
      bag.string().c_str());
  std::printf("%s", sensors::SuggestTopicMap(summary).c_str());
  return 0;
}

void PrintStream(const sensors::RosbagImportStream& s) {
  std::printf("  %-16s %-16s %-24s %8zu", s.id.c_str(),
              std::string(sensors::RosTopicKindName(s.kind)).c_str(), s.topic.c_str(), s.count);
  if (s.count > 1 && s.last_stamp_ns > s.first_stamp_ns) {
    std::printf(" %7.1f Hz",
                static_cast<double>(s.count - 1) / ToSeconds(s.last_stamp_ns - s.first_stamp_ns));
  }
  std::printf("  frame '%s'", s.frame_id.c_str());
  if (s.latency_s) std::printf(", latency %.3f s", *s.latency_s);
  if (s.kind == sensors::RosTopicKind::kLidar) {
    std::printf(", %zu points, time field %s", s.lidar_points,
                s.time_field.empty() ? "none (t = 0)" : ("'" + s.time_field + "'").c_str());
  }
  if (s.skipped > 0) {
    std::printf(", %zu %s skipped", s.skipped,
                s.kind == sensors::RosTopicKind::kLidar ? "non-finite points" : "messages");
  }
  if (s.arrivals_at_stamp > 0) {
    std::printf(", %zu received before their stamp (arrival = stamp)", s.arrivals_at_stamp);
  }
  std::printf("\n");
}

}  // namespace

int RunImport(const std::vector<std::string>& argv) {
  const auto parsed =
      ParseCommand({"import", kUsage, {"quiet"}, {"topics", "out", "time-offset-s"}, 2, {}}, argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs* args = &std::get<CliArgs>(parsed);
  try {
    if (args->positional()[0] != "rosbag") {
      throw std::invalid_argument("unknown source '" + args->positional()[0] +
                                  "' (expected: rosbag)");
    }
    const std::filesystem::path bag = args->positional()[1];
    const auto topics = args->Option("topics");
    const auto out = args->Option("out");
    if (!topics) {
      if (out) throw std::invalid_argument("--out needs --topics MAP.yaml (list the bag first)");
      return ListTopics(bag);
    }
    if (!out) throw std::invalid_argument("--topics needs --out LOG");
    sensors::RosbagImportOptions options;
    options.time_offset_ns = FromSeconds(args->Double("time-offset-s").value_or(0.0));
    const sensors::RosTopicMap map = sensors::LoadRosTopicMap(*topics);
    const sensors::RosbagImportResult result = sensors::ImportRosbag(bag, map, *out, options);
    if (!args->Flag("quiet")) {
      std::printf("%s -> %s\n", bag.string().c_str(), out->c_str());
      for (const sensors::RosbagImportStream& s : result.streams) PrintStream(s);
      for (const sensors::RosbagTopicInfo& t : result.unmapped) {
        std::printf("  not imported: %s (%s)\n", t.topic.c_str(), t.datatype.c_str());
      }
    }
    for (const std::string& note : result.notes) {
      std::fprintf(stderr, "statebench import: note: %s\n", note.c_str());
    }
    if (result.error) {
      std::fprintf(stderr, "statebench import: %s\n", result.error->c_str());
      std::fprintf(stderr, "statebench import: %s holds what was converted before this error\n",
                   out->c_str());
      return 2;
    }
    return 0;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "statebench import: %s\n%s", e.what(), kUsage);
    return 2;
  } catch (...) {
    return ExitCodeForCurrentException("import");
  }
}

}  // namespace statebench::app
