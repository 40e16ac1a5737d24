// The topic map of a ROS1 bag import (MAP.yaml, docs/real-data.md): which bag topic becomes which
// sensor of the recorded log (id, setup type), with the overrides a bag cannot carry (frames,
// mounts, latencies, covariances its messages do not give) and static transforms missing from
// its /tf_static. `statebench export rosbag` writes one that imports its bag back.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/geodetic.hpp"
#include "core/se3.hpp"
#include "core/yaml_node.hpp"

namespace statebench::sensors {

// What a topic becomes; named as the sensor-setup types (docs/sensor-setup.md).
enum class RosTopicKind {
  kImu,           // sensor_msgs/Imu -> imu/<id>.csv
  kGnss,          // sensor_msgs/NavSatFix -> gnss/<id>.csv
  kBodyVelocity,  // nav_msgs/Odometry, geometry_msgs/Twist(WithCovariance)Stamped -> body_velocity
  kSpeedEncoder,  // the same twists' linear.x -> speed/<id>.csv
  kSteeringEncoder,  // sensor_msgs/JointState position of one joint -> steering/<id>.csv
  kWheelEncoders,    // sensor_msgs/JointState velocity of four joints -> wheels/<id>.csv
  kLidar,            // sensor_msgs/PointCloud2 -> lidar/<id>.csv + one PCD per sweep
  // geometry_msgs/Twist(WithCovariance)Stamped in ENU (nmea_navsat_driver's /vel): the Doppler
  // velocity of the gnss entry with the same id, joined to its fixes (velocity columns).
  kGnssVelocity,
};

// "imu", "gnss", "body_velocity", "speed_encoder", "steering_encoder", "wheel_encoders", "lidar",
// "gnss_velocity".
std::string_view RosTopicKindName(RosTopicKind kind);

struct RosTopicEntry {
  std::string topic;  // as in the bag, e.g. "/imu/data"
  std::string id;     // sensor id in the log
  RosTopicKind kind = RosTopicKind::kImu;
  std::optional<std::string> frame_id;   // instead of the messages' frame
  std::optional<SE3> T_body_sensor;      // instead of the static transforms
  std::optional<double> latency_s;       // instead of the largest receive - stamp delay
  std::string estimator;  // the setup entry's `estimator:` block, flow YAML (empty: none)
  std::optional<Vec3> position_sigma_m;  // gnss: replaces the fixes' covariance (east, north, up)
  std::optional<Vec6> twist_sigma;    // body_velocity: replaces the twist covariance (m/s, rad/s)
  std::optional<Vec3> velocity_sigma_mps;  // gnss_velocity: replaces its covariance (E, N, U)
  std::string joint;                  // steering_encoder: joint name (default: the id)
  std::array<std::string, 4> joints;  // wheel_encoders: FL FR RL RR (default: <id>_fl ...)
  std::optional<std::string>
      time_field;                      // lidar: per-point time field (default t, time, timestamp)
  std::optional<double> time_scale_s;  // lidar: seconds per unit of the time field
  std::string where;                   // "file:line:column" of the entry, for messages
};

struct RosStaticTransform {
  std::string parent;
  std::string child;
  SE3 T_parent_child;  // maps child-frame points into the parent frame
  std::string where;
};

struct RosTopicMap {
  std::string source;                    // file it was loaded from
  std::string base_frame = "base_link";  // the body frame of setup.yaml (REP-105 base_link)
  std::string scenario;                  // log.yaml's scenario text (default: the bag's file name)
  std::optional<GeodeticPoint> origin;   // log.yaml's WGS84 anchor
  std::vector<RosTopicEntry> topics;
  std::vector<RosStaticTransform> static_transforms;  // added to (and overriding) /tf_static
};

// InputError naming file:line:column and field on: unknown key or type, missing topic or id,
// duplicate id (a gnss_velocity entry shares the id of its gnss entry, one per gnss), a
// gnss_velocity without a gnss entry of its id, an id that cannot name a file, an option of
// another type's topic, a sigma that is not positive.
RosTopicMap LoadRosTopicMap(const std::filesystem::path& path);
RosTopicMap ParseRosTopicMap(const YamlNode& root);

// The map as YAML (numbers in shortest round-trip form; loads back to the same map).
std::string RosTopicMapYaml(const RosTopicMap& map, const std::string& header_comment);

// Frame ids compare without a leading '/' (tf2 drops it; older bags have it).
std::string NormalizedFrameId(std::string_view frame_id);

}  // namespace statebench::sensors
