// The bag -> log conversion loop (compiled as C++17: ros1_messages.hpp).
#include "sensors/rosbag_import.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <set>

#include "sensors/gnss_velocity_joiner.hpp"
#include "sensors/log_writer.hpp"
#include "sensors/ros1_bag.hpp"
#include "sensors/ros1_messages.hpp"
#include "sensors/sensor_mounts.hpp"
#include "sensors/static_transform_tree.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;

// One message converted for one topic-map entry (nullopt measurement: skipped).
struct Converted {
  std::optional<Measurement> measurement;
  std::string frame_id;
  TimeNs stamp_ns = 0;
  // The latency is counted after this (a lidar sweep's last point); nullopt: an empty sweep.
  std::optional<TimeNs> last_point_ns;
  std::size_t skipped = 0;  // lidar points
  std::string time_field;
};

template <typename Msg>
boost::shared_ptr<Msg> Instantiate(const rosbag::MessageInstance& m) {
  boost::shared_ptr<Msg> msg = m.instantiate<Msg>();
  if (!msg) {
    throw InputError("message does not match the definition of " + m.getDataType() +
                     " this program knows (md5sum " + m.getMD5Sum() + ")");
  }
  return msg;
}

TimeNs StampOf(const std_msgs::Header& header, TimeNs offset_ns) {
  return static_cast<TimeNs>(header.stamp.toNSec()) + offset_ns;
}

// The twist types: body velocity (with or without covariance) or their linear.x as a speed.
template <typename Msg>
Converted FromTwist(const Msg& msg, const geometry_msgs::Twist& twist,
                    const geometry_msgs::TwistWithCovariance* with_covariance,
                    const RosTopicEntry& e) {
  Converted c;
  if (e.kind == RosTopicKind::kSpeedEncoder) {
    VehicleSpeed s;
    s.speed_mps = ros1::SpeedFromRos(twist);
    c.measurement = s;
  } else if (with_covariance != nullptr) {
    c.measurement = ros1::BodyVelocityFromRos(*with_covariance, e);
  } else {
    c.measurement = ros1::BodyVelocityFromRos(twist, e);
  }
  return c;
}

Converted Convert(const rosbag::MessageInstance& m, const RosTopicEntry& e, TimeNs offset_ns) {
  const std::string& type = m.getDataType();
  Converted c;
  const std_msgs::Header* header = nullptr;
  if (type == "sensor_msgs/Imu") {
    const auto msg = Instantiate<sensor_msgs::Imu>(m);
    c.measurement = ros1::ImuFromRos(*msg);
    header = &msg->header;
    c.frame_id = header->frame_id;
    c.stamp_ns = StampOf(*header, offset_ns);
  } else if (type == "sensor_msgs/NavSatFix") {
    const auto msg = Instantiate<sensor_msgs::NavSatFix>(m);
    if (auto fix = ros1::GnssFixFromRos(*msg, e)) c.measurement = *fix;
    c.frame_id = msg->header.frame_id;
    c.stamp_ns = StampOf(msg->header, offset_ns);
  } else if (type == "nav_msgs/Odometry") {
    const auto msg = Instantiate<nav_msgs::Odometry>(m);
    c = FromTwist(*msg, msg->twist.twist, &msg->twist, e);
    c.frame_id = msg->child_frame_id;  // REP-105: the twist is in the child frame
    c.stamp_ns = StampOf(msg->header, offset_ns);
  } else if (type == "geometry_msgs/TwistStamped") {
    const auto msg = Instantiate<geometry_msgs::TwistStamped>(m);
    c = FromTwist(*msg, msg->twist, nullptr, e);
    c.frame_id = msg->header.frame_id;
    c.stamp_ns = StampOf(msg->header, offset_ns);
  } else if (type == "geometry_msgs/TwistWithCovarianceStamped") {
    const auto msg = Instantiate<geometry_msgs::TwistWithCovarianceStamped>(m);
    c = FromTwist(*msg, msg->twist.twist, &msg->twist, e);
    c.frame_id = msg->header.frame_id;
    c.stamp_ns = StampOf(msg->header, offset_ns);
  } else if (type == "sensor_msgs/JointState") {
    const auto msg = Instantiate<sensor_msgs::JointState>(m);
    if (e.kind == RosTopicKind::kSteeringEncoder) {
      if (auto s = ros1::SteeringFromRos(*msg, e)) c.measurement = *s;
    } else if (auto w = ros1::WheelsFromRos(*msg, e)) {
      c.measurement = *w;
    }
    c.frame_id = msg->header.frame_id;
    c.stamp_ns = StampOf(msg->header, offset_ns);
  } else if (type == "sensor_msgs/PointCloud2") {
    const auto msg = Instantiate<sensor_msgs::PointCloud2>(m);
    c.stamp_ns = StampOf(msg->header, offset_ns);
    ros1::PointCloudTiming timing;
    LidarScan scan;
    scan.points = std::make_shared<const std::vector<LidarPoint>>(
        ros1::PointsFromRos(*msg, e, &c.stamp_ns, &c.skipped, &timing));
    if (!scan.points->empty()) {
      float t_last = 0.f;
      for (const LidarPoint& p : *scan.points) t_last = std::max(t_last, p.t);
      c.last_point_ns = c.stamp_ns + FromSeconds(t_last);
    }
    c.time_field = timing.field;
    c.measurement = std::move(scan);
    c.frame_id = msg->header.frame_id;
  } else {
    throw InputError("cannot convert a " + type);  // the map was checked before: not reached
  }
  if (e.kind != RosTopicKind::kLidar) c.last_point_ns = c.stamp_ns;
  c.frame_id = NormalizedFrameId(c.frame_id);
  return c;
}

// A gnss_velocity message: its stamp and the ENU velocity with sigmas.
std::pair<TimeNs, GnssVelocity> ConvertGnssVelocity(const rosbag::MessageInstance& m,
                                                    const RosTopicEntry& e, TimeNs offset_ns) {
  if (m.getDataType() == "geometry_msgs/TwistStamped") {
    const auto msg = Instantiate<geometry_msgs::TwistStamped>(m);
    return {StampOf(msg->header, offset_ns), ros1::GnssVelocityFromRos(msg->twist, nullptr, e)};
  }
  const auto msg = Instantiate<geometry_msgs::TwistWithCovarianceStamped>(m);
  return {StampOf(msg->header, offset_ns),
          ros1::GnssVelocityFromRos(msg->twist.twist, &msg->twist.covariance, e)};
}

void SetHeader(Measurement& m, MeasurementHeader header) {
  std::visit([&header](auto& x) { x.header = std::move(header); }, m);
}

struct Stream {
  const RosTopicEntry* entry = nullptr;
  RosbagImportStream stats;
  std::optional<TimeNs> last_stamp_ns;
  std::optional<TimeNs> max_delay_ns;
};

void Record(Stream& s, const Converted& c, TimeNs received_ns, LogWriter& writer) {
  const RosTopicEntry& e = *s.entry;
  const std::string frame = e.frame_id.value_or(c.frame_id);
  if (s.stats.count == 0) {
    s.stats.frame_id = frame;
  } else if (frame != s.stats.frame_id) {
    throw InputError("frame_id '" + frame + "' differs from the topic's earlier '" +
                     s.stats.frame_id + "'");
  }
  if (s.last_stamp_ns && c.stamp_ns <= *s.last_stamp_ns) {
    throw InputError("header stamp " + std::to_string(c.stamp_ns) +
                     " ns is not after the previous message's " + std::to_string(*s.last_stamp_ns) +
                     " ns (stamps of a sensor must increase)");
  }
  if (c.last_point_ns) {
    const TimeNs delay_ns = received_ns - *c.last_point_ns;
    s.max_delay_ns = std::max(s.max_delay_ns.value_or(delay_ns), delay_ns);
  }
  MeasurementHeader header{e.id, c.stamp_ns, std::max(received_ns, c.stamp_ns)};
  if (received_ns < c.stamp_ns) ++s.stats.arrivals_at_stamp;
  Measurement measurement = *c.measurement;
  SetHeader(measurement, header);
  writer.Write(measurement);
  if (const auto* scan = std::get_if<LidarScan>(&measurement)) {
    s.stats.lidar_points += scan->points->size();
    s.stats.time_field = c.time_field;
  }
  if (s.stats.count == 0) s.stats.first_stamp_ns = c.stamp_ns;
  s.stats.last_stamp_ns = c.stamp_ns;
  s.last_stamp_ns = c.stamp_ns;
  ++s.stats.count;
}

// setup.yaml from the streams that have measurements; the first stream whose frame the static
// transforms do not reach gives `missing`.
std::string SetupYaml(const RosTopicMap& map, const std::vector<Stream>& streams,
                      const StaticTransformTree& tree, const fs::path& bag,
                      std::optional<std::string>* missing) {
  std::vector<SensorMount> mounts;
  for (const Stream& s : streams) {
    if (s.stats.count == 0 || s.entry->kind == RosTopicKind::kGnssVelocity) continue;
    SensorMount mount;
    mount.type = std::string(RosTopicKindName(s.entry->kind));
    mount.id = s.entry->id;
    mount.latency_s = s.stats.latency_s;
    mount.estimator = s.entry->estimator;
    mount.comment =
        "topic " + s.stats.topic + " (" + s.stats.datatype + "), frame '" + s.stats.frame_id + "'";
    if (s.entry->T_body_sensor) {
      mount.T_body_sensor = *s.entry->T_body_sensor;
    } else if (const auto T = tree.Lookup(map.base_frame, s.stats.frame_id)) {
      mount.T_body_sensor = *T;
    } else {
      if (!*missing) {
        *missing = "topic '" + s.stats.topic + "' (sensor '" + s.entry->id +
                   "'): no static transform connects the base frame '" + map.base_frame +
                   "' to its frame '" + s.stats.frame_id + "' (in " +
                   std::string(ros1::kTfStaticTopic) +
                   " or the topic map's static_transforms); give T_body_sensor for the topic";
      }
      continue;
    }
    mounts.push_back(std::move(mount));
  }
  const std::string name = map.scenario.empty() ? bag.stem().string() : map.scenario;
  return SensorMountsYaml(name, mounts,
                          "# Sensor setup of a log imported from " + bag.filename().string() +
                              " by statebench import rosbag (docs/real-data.md): mounts from "
                              "/tf_static and the topic map\n# (base frame '" +
                              map.base_frame +
                              "'), latency_s the largest receive - stamp delay seen.\n");
}

}  // namespace

std::string ros1::FrameOfMessage(const rosbag::MessageInstance& m) {
  const std::string& type = m.getDataType();
  for (const RosTopicKind kind :
       {RosTopicKind::kImu, RosTopicKind::kGnss, RosTopicKind::kBodyVelocity,
        RosTopicKind::kSteeringEncoder, RosTopicKind::kLidar}) {
    if (!RosbagImportAccepts(kind, type)) continue;
    RosTopicEntry entry;  // options that let any decodable message convert
    entry.kind = kind;
    entry.twist_sigma = Vec6::Ones();
    entry.position_sigma_m = Vec3::Ones();
    try {
      return Convert(m, entry, 0).frame_id;
    } catch (const std::exception&) {
      return "";
    }
  }
  return "";
}

RosbagImportResult ImportRosbag(const fs::path& bag_path, const RosTopicMap& map,
                                const fs::path& out_dir, const RosbagImportOptions& options) {
  const std::unique_ptr<rosbag::Bag> bag = ros1::OpenBagForReading(bag_path);
  std::map<std::string, std::string> datatypes;
  std::map<std::string, std::size_t> message_counts;
  {
    rosbag::View all(*bag);
    for (const rosbag::ConnectionInfo* c : all.getConnections()) datatypes[c->topic] = c->datatype;
  }
  CheckTopicMap(map, datatypes, bag_path);

  RosbagImportResult result;
  std::vector<Stream> streams(map.topics.size());
  std::set<std::string> topics;
  for (std::size_t i = 0; i < map.topics.size(); ++i) {
    const RosTopicEntry& e = map.topics[i];
    streams[i].entry = &e;
    streams[i].stats.topic = e.topic;
    streams[i].stats.datatype = datatypes.at(e.topic);
    streams[i].stats.id = e.id;
    streams[i].stats.kind = e.kind;
    topics.insert(e.topic);
  }
  const bool read_tf = datatypes.count(ros1::kTfStaticTopic) > 0 &&
                       ros1::IsTfMessage(datatypes.at(ros1::kTfStaticTopic));
  for (const auto& [topic, datatype] : datatypes) {
    if (topics.count(topic) == 0 && !(read_tf && topic == ros1::kTfStaticTopic)) {
      result.unmapped.push_back(RosbagTopicInfo{topic, datatype, 0, "", 0.0});
    }
  }
  if (read_tf) topics.insert(ros1::kTfStaticTopic);

  LogWriterOptions writer_options;
  writer_options.scenario = map.scenario.empty() ? bag_path.filename().string() : map.scenario;
  writer_options.origin = map.origin;
  std::map<std::string, Stream*> velocity_stream_of;  // gnss id -> its gnss_velocity stream
  for (Stream& s : streams) {
    if (s.entry->kind != RosTopicKind::kGnssVelocity) continue;
    velocity_stream_of[s.entry->id] = &s;
    writer_options.gnss_velocity_ids.insert(s.entry->id);
  }
  GnssVelocityJoiner joiner;
  LogWriter writer(out_dir, writer_options);
  StaticTransformTree tree;
  const std::vector<std::string> topic_list(topics.begin(), topics.end());
  rosbag::View view(*bag, rosbag::TopicQuery(topic_list));
  // The message being converted, for the error message (topic and type live in the bag's
  // connection records, which outlast the loop's iterator).
  const std::string* topic = nullptr;
  const std::string* datatype = nullptr;
  ros::Time bag_time;
  std::size_t index = 0;
  try {
    for (const rosbag::MessageInstance& m : view) {
      topic = &m.getTopic();
      datatype = &m.getDataType();
      bag_time = m.getTime();
      index = message_counts[*topic]++;
      if (read_tf && m.getTopic() == ros1::kTfStaticTopic) {
        for (const RosStaticTransform& s : ros1::StaticTransformsOf(m)) {
          tree.Set(s.parent, s.child, s.T_parent_child);
        }
        continue;
      }
      const TimeNs received_ns = static_cast<TimeNs>(m.getTime().toNSec()) + options.time_offset_ns;
      for (Stream& s : streams) {
        if (s.entry->topic != m.getTopic()) continue;
        if (s.entry->kind == RosTopicKind::kGnssVelocity) {
          const auto [stamp_ns, velocity] =
              ConvertGnssVelocity(m, *s.entry, options.time_offset_ns);
          ++s.stats.skipped;  // until joined to a fix (below)
          joiner.AddVelocity(s.entry->id, stamp_ns, velocity);
          continue;
        }
        const Converted c = Convert(m, *s.entry, options.time_offset_ns);
        if (!c.measurement) {
          ++s.stats.skipped;
          continue;
        }
        s.stats.skipped += c.skipped;
        const auto velocity_stream = velocity_stream_of.find(s.entry->id);
        if (s.entry->kind != RosTopicKind::kGnss || velocity_stream == velocity_stream_of.end()) {
          Record(s, c, received_ns, writer);
          continue;
        }
        Stream& v = *velocity_stream->second;
        joiner.AddFix(s.entry->id, c.stamp_ns, received_ns,
                      [&s, &v, &writer, c, received_ns](const std::optional<GnssVelocity>& vel) {
                        Converted joined = c;
                        std::get<GnssFix>(*joined.measurement).velocity = vel;
                        Record(s, joined, received_ns, writer);
                        if (!vel) return;
                        if (v.stats.count == 0) v.stats.first_stamp_ns = c.stamp_ns;
                        v.stats.last_stamp_ns = c.stamp_ns;
                        ++v.stats.count;
                        --v.stats.skipped;
                      });
      }
      joiner.Advance(received_ns);
    }
  } catch (const std::exception& e) {  // InputError, rosbag::BagException
    std::string where = bag_path.string();
    if (topic != nullptr) {
      where += ": topic '" + *topic + "' message " + std::to_string(index) + " (" + *datatype +
               ", bag time " + ros1::BagTimeText(bag_time) + ")";
    }
    result.error = where + ": " + e.what();
  }
  try {  // the fixes still waiting for a velocity (also after an error: they came before it)
    joiner.Flush();
  } catch (const std::exception& e) {
    if (!result.error) result.error = bag_path.string() + ": " + e.what();
  }

  for (const RosStaticTransform& s : map.static_transforms) {
    tree.Set(s.parent, s.child, s.T_parent_child);
  }
  for (Stream& s : streams) {
    if (s.entry->latency_s) {
      s.stats.latency_s = s.entry->latency_s;
    } else if (s.max_delay_ns) {
      // Divided (not multiplied by 1e-9): 30 ms gives exactly the double of "0.03".
      s.stats.latency_s = static_cast<double>(std::max<TimeNs>(*s.max_delay_ns, 0)) / 1e9;
    }
    if (s.stats.count > 0 && s.stats.frame_id.empty() && !s.entry->T_body_sensor &&
        s.entry->kind != RosTopicKind::kGnssVelocity) {
      result.notes.push_back("topic '" + s.stats.topic +
                             "' has no frame_id: mounted at the base frame '" + map.base_frame +
                             "' (give frame_id or T_body_sensor in the topic map)");
      s.stats.frame_id = map.base_frame;
    }
    result.streams.push_back(s.stats);
  }
  std::optional<std::string> missing;
  writer.WriteSetup(SetupYaml(map, streams, tree, bag_path, &missing));
  if (missing && !result.error) result.error = bag_path.string() + ": " + *missing;
  writer.Close();
  return result;
}

}  // namespace statebench::sensors
