// The log -> bag conversion loop (compiled as C++17: ros1_messages.hpp).
#include "sensors/rosbag_export.hpp"

#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>

#include <map>

#include "core/error.hpp"
#include "sensors/log_reader.hpp"
#include "sensors/ros1_messages.hpp"
#include "sensors/sensor_mounts.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;

constexpr const char* kCallerId = "/statebench";

std::optional<RosTopicKind> KindOf(LogStreamType type) {
  switch (type) {
    case LogStreamType::kImu:
      return RosTopicKind::kImu;
    case LogStreamType::kGnss:
      return RosTopicKind::kGnss;
    case LogStreamType::kWheelSpeeds:
      return RosTopicKind::kWheelEncoders;
    case LogStreamType::kVehicleSpeed:
      return RosTopicKind::kSpeedEncoder;
    case LogStreamType::kSteeringAngle:
      return RosTopicKind::kSteeringEncoder;
    case LogStreamType::kLidar:
      return RosTopicKind::kLidar;
    case LogStreamType::kBodyVelocity:
      return RosTopicKind::kBodyVelocity;
    case LogStreamType::kDualAntennaHeading:
      return std::nullopt;  // no ROS message type for a baseline heading
  }
  return std::nullopt;
}

// /tf_static: one message with every mount, latched (rosbag play republishes it to late
// subscribers as a latched publisher would).
void WriteStaticTransforms(rosbag::Bag& bag, const std::vector<SensorMount>& mounts,
                           const std::string& base_frame, const ros::Time& time) {
  tf2_msgs::TFMessage msg;
  for (const SensorMount& m : mounts) {
    geometry_msgs::TransformStamped ts;
    ts.header.stamp = time;
    ts.header.frame_id = base_frame;
    ts.child_frame_id = m.id;
    const Vec3& t = m.T_body_sensor.translation();
    const Quat& q = m.T_body_sensor.rotation();
    ts.transform.translation.x = t.x();
    ts.transform.translation.y = t.y();
    ts.transform.translation.z = t.z();
    ts.transform.rotation.w = q.w();
    ts.transform.rotation.x = q.x();
    ts.transform.rotation.y = q.y();
    ts.transform.rotation.z = q.z();
    msg.transforms.push_back(ts);
  }
  auto header = boost::make_shared<ros::M_string>();
  (*header)["type"] = ros::message_traits::datatype(msg);
  (*header)["md5sum"] = ros::message_traits::md5sum(msg);
  (*header)["message_definition"] = ros::message_traits::definition(msg);
  (*header)["callerid"] = kCallerId;
  (*header)["latching"] = "1";
  bag.write("/tf_static", time, msg, header);
}

// Writes the message; returns its datatype.
template <typename Msg>
std::string Put(rosbag::Bag& bag, const std::string& topic, const ros::Time& time, const Msg& msg) {
  bag.write(topic, time, msg);
  return ros::message_traits::datatype(msg);
}

class BagWriter {
 public:
  BagWriter(rosbag::Bag& bag, TimeNs offset_ns) : bag_(bag), offset_ns_(offset_ns) {}

  // The fix's velocity as a twist in ENU on its own topic (nmea_navsat_driver's /vel), at the
  // fix's stamp and arrival; returns the datatype written.
  std::string WriteGnssVelocity(const GnssFix& fix, const std::string& topic) {
    GnssFix copy = fix;
    copy.header = Shifted(fix.header);
    return Put(bag_, topic, BagTime(copy.header),
               ros1::GnssVelocityToRos(copy, fix.header.sensor_id));
  }

  // Returns the datatype written.
  std::string Write(const Measurement& m, const std::string& topic) {
    const MeasurementHeader& h = HeaderOf(m);
    const MeasurementHeader shifted = Shifted(h);
    const ros::Time time = BagTime(shifted);
    const std::string& id = h.sensor_id;
    return std::visit(
        [&](const auto& x) -> std::string {
          using T = std::decay_t<decltype(x)>;
          T copy = x;
          copy.header = shifted;
          if constexpr (std::is_same_v<T, ImuSample>) {
            return Put(bag_, topic, time, ros1::ImuToRos(copy, id));
          } else if constexpr (std::is_same_v<T, GnssFix>) {
            return Put(bag_, topic, time, ros1::GnssFixToRos(copy, id));
          } else if constexpr (std::is_same_v<T, WheelSpeeds>) {
            return Put(
                bag_, topic, time,
                ros1::WheelsToRos(copy, {id + "_fl", id + "_fr", id + "_rl", id + "_rr"}, id));
          } else if constexpr (std::is_same_v<T, VehicleSpeed>) {
            return Put(bag_, topic, time, ros1::SpeedToRos(copy, id));
          } else if constexpr (std::is_same_v<T, SteeringAngle>) {
            return Put(bag_, topic, time, ros1::SteeringToRos(copy, id, id));
          } else if constexpr (std::is_same_v<T, LidarScan>) {
            return Put(bag_, topic, time, ros1::PointsToRos(copy, id));
          } else if constexpr (std::is_same_v<T, BodyVelocity>) {
            return Put(bag_, topic, time, ros1::BodyVelocityToRos(copy, id));
          } else {
            static_assert(std::is_same_v<T, DualAntennaHeading>);
            return std::string();  // KindOf() keeps these out
          }
        },
        m);
  }

 private:
  MeasurementHeader Shifted(const MeasurementHeader& h) const {
    return {h.sensor_id, h.stamp_ns + offset_ns_, h.arrival_ns + offset_ns_};
  }
  static ros::Time BagTime(const MeasurementHeader& shifted) {
    const ros::Time time = ros1::RosTime(shifted.arrival_ns);
    if (time < ros::TIME_MIN) {
      throw InputError(
          "arrival 0 ns cannot be a ROS1 bag time (the earliest is 1 ns): give a "
          "time offset");
    }
    return time;
  }

  rosbag::Bag& bag_;
  TimeNs offset_ns_;
};

}  // namespace

RosbagExportResult ExportRosbag(const fs::path& log_dir, const fs::path& bag_path,
                                const RosbagExportOptions& options) {
  LogReader reader(log_dir);
  std::vector<SensorMount> mounts;
  if (const auto setup = reader.setup_file()) mounts = ReadSensorMounts(*setup);
  std::error_code ec;
  if (fs::exists(bag_path, ec)) {
    throw InputError(bag_path.string() + ": already exists; remove it or choose another --out");
  }

  RosbagExportResult result;
  RosTopicMap& map = result.topic_map;
  map.base_frame = options.base_frame;
  map.scenario = reader.manifest().scenario;
  map.origin = reader.manifest().origin;

  rosbag::Bag bag;
  try {
    bag.open(bag_path.string(), rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path.string() + ": cannot create the bag: " + e.what());
  }
  BagWriter writer(bag, options.time_offset_ns);
  std::map<std::string, std::size_t> stream_of;  // sensor id -> index in result.streams
  std::string current;                           // the measurement being written, for errors
  try {
    std::optional<Measurement> m = reader.Next();
    if (!mounts.empty()) {
      ros::Time time = ros::TIME_MIN;
      if (m) time = std::max(time, ros1::RosTime(HeaderOf(*m).arrival_ns + options.time_offset_ns));
      WriteStaticTransforms(bag, mounts, options.base_frame, time);
      result.static_transforms = mounts.size();
    }
    for (; m; m = reader.Next()) {
      const std::string& id = HeaderOf(*m).sensor_id;
      current = "sensor '" + id + "' stamp " + std::to_string(HeaderOf(*m).stamp_ns) + " ns: ";
      auto [it, added] = stream_of.emplace(id, result.streams.size());
      if (added) {
        RosbagExportStream s;
        s.id = id;
        s.type = StreamTypeOf(*m);
        if (const auto kind = KindOf(s.type)) {
          s.topic = "/" + id;
          RosTopicEntry entry;
          entry.topic = s.topic;
          entry.id = id;
          entry.kind = *kind;
          entry.joint = id;
          entry.joints = {id + "_fl", id + "_fr", id + "_rl", id + "_rr"};
          for (const SensorMount& mount : mounts) {
            if (mount.id == id) entry.estimator = mount.estimator;  // what the estimators are told
          }
          map.topics.push_back(entry);
        }
        result.streams.push_back(s);
      }
      RosbagExportStream& s = result.streams[it->second];
      if (s.topic.empty()) continue;
      s.datatype = writer.Write(*m, s.topic);
      ++s.count;
      if (const auto* fix = std::get_if<GnssFix>(&*m); fix && fix->velocity) {
        // Sensor ids hold no '/': "<id>/vel" names no other stream.
        const auto [v, first] = stream_of.emplace(id + "/vel", result.streams.size());
        if (first) {
          RosbagExportStream velocity;
          velocity.id = id;
          velocity.type = LogStreamType::kGnss;
          velocity.topic = "/" + id + "/vel";
          RosTopicEntry entry;
          entry.topic = velocity.topic;
          entry.id = id;
          entry.kind = RosTopicKind::kGnssVelocity;
          map.topics.push_back(entry);
          result.streams.push_back(velocity);
        }
        RosbagExportStream& vs = result.streams[v->second];
        vs.datatype = writer.WriteGnssVelocity(*fix, vs.topic);
        ++vs.count;
      }
    }
    if (reader.error()) result.error = *reader.error();
  } catch (const std::exception& e) {  // InputError, rosbag::BagException
    result.error = log_dir.string() + ": " + current + e.what();
  }
  bag.close();
  return result;
}

}  // namespace statebench::sensors
