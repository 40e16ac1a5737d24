// statebench import rosbag on bags written message by message: what each field of each message
// type becomes (docs/real-data.md), the mounts composed from /tf_static and the topic map, the
// latencies, the point clouds of three drivers' layouts, and the suggested topic map.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>

#include "core/yaml_node.hpp"
#include "ros1_test_bag.hpp"
#include "sensors/rosbag_import.hpp"
#include "sensors/sensor_mounts.hpp"

namespace statebench::sensors {
namespace {

using testing::OfSensor;
using testing::Ros;
using testing::RosHeader;
using testing::TestBag;

constexpr TimeNs kMs = kNsPerMillisecond;
constexpr TimeNs kT0 = 1'700'000'000 * kNsPerSecond;  // stamps as real bags have them

std::map<std::string, SensorMount> MountsOf(const std::filesystem::path& log) {
  std::map<std::string, SensorMount> out;
  for (const SensorMount& m : ReadSensorMounts(log / "setup.yaml")) out[m.id] = m;
  return out;
}

TEST(RosbagImport, ConvertsEveryMessageTypeWithItsMountAndLatency) {
  TestBag b("types");
  const Quat q_base_chassis(Eigen::AngleAxisd(0.5 * M_PI, Vec3::UnitZ()));
  b.StaticTransform("base_link", "chassis", Vec3(1.0, 0.0, 0.0), q_base_chassis);
  b.StaticTransform("/chassis", "imu_link", Vec3(0.0, 0.0, 0.5), Quat::Identity());
  b.StaticTransform("base_link", "gps", Vec3(0.2, 0.0, 1.5), Quat::Identity());
  for (int k = 0; k < 5; ++k) {
    const TimeNs t = kT0 + k * 10 * kMs;
    sensor_msgs::Imu imu;
    imu.header = RosHeader(t, "imu_link");
    imu.orientation_covariance[0] = -1.0;
    imu.angular_velocity.x = 0.01 * k;
    imu.angular_velocity.z = -0.3;
    imu.linear_acceleration.z = 9.81;
    b.Write("/imu/data", k == 2 ? t - kMs : t + 2 * kMs, imu);  // message 2: received early

    sensor_msgs::NavSatFix fix;
    fix.header = RosHeader(t, "gps");
    const std::int8_t statuses[5] = {-1, 0, 2, 2, 1};
    const double variances[5] = {1.0, 1.0, 1e-4, 0.25, 0.5};
    fix.status.status = statuses[k];
    fix.latitude = k == 0 ? std::numeric_limits<double>::quiet_NaN() : 48.0 + 1e-6 * k;
    fix.longitude = 2.0;
    fix.altitude = 130.0;
    fix.position_covariance = {
        variances[k],    0.1 * variances[k], 0, 0.1 * variances[k], variances[k], 0, 0, 0,
        4 * variances[k]};
    fix.position_covariance_type = sensor_msgs::NavSatFix::COVARIANCE_TYPE_APPROXIMATED;
    b.Write("/fix", t + 100 * kMs, fix);

    nav_msgs::Odometry odom;
    odom.header = RosHeader(t, "odom");
    odom.child_frame_id = "base_link";
    odom.pose.pose.position.x = 100.0;  // the pose is not imported
    odom.twist.twist.linear.x = 1.5 + k;
    odom.twist.twist.angular.z = 0.2;
    for (int i = 0; i < 6; ++i) odom.twist.covariance[static_cast<std::size_t>(7 * i)] = 1e-2;
    odom.twist.covariance[2 * 7] = 1e6;  // vz unmeasured
    b.Write("/odom", t + 5 * kMs, odom);

    geometry_msgs::TwistStamped cmd;
    cmd.header = RosHeader(t, "base_link");
    cmd.twist.linear.x = 2.0;
    b.Write("/twist", t + 5 * kMs, cmd);

    geometry_msgs::TwistWithCovarianceStamped speed;
    speed.header = RosHeader(t, "rear_axle");
    speed.twist.twist.linear.x = 3.25 - k;
    b.Write("/speed", t + 5 * kMs, speed);

    sensor_msgs::JointState joints;
    joints.header = RosHeader(t, "");
    joints.name = {"steer", "rr", "fl", "arm", "rl", "fr"};
    joints.position = {0.01 * k, 0, 0, 1.0, 0, 0};
    joints.velocity = {0, 4.0, 1.0, 0, 3.0, 2.0};
    b.Write("/joint_states", t + kMs, joints);
    sensor_msgs::JointState arm;  // other joints in separate messages: skipped
    arm.header = RosHeader(t + kMs, "");
    arm.name = {"arm"};
    arm.position = {2.0};
    b.Write("/joint_states", t + 2 * kMs, arm);
  }
  b.Write("/ignored", kT0, geometry_msgs::TwistStamped());
  b.Close();
  b.WriteMap(R"(origin: {latitude_deg: 48.0, longitude_deg: 2.0, altitude_m: 130.0}
topics:
  - {topic: /imu/data, id: imu, type: imu}
  - {topic: /fix, id: gnss, type: gnss, latency_s: 0.2}
  - {topic: /odom, id: wheel_odom, type: body_velocity}
  - {topic: /twist, id: cmd, type: body_velocity, twist_sigma: [0.1, 0.2, 0.3, 1, 2, 3]}
  - {topic: /speed, id: speed, type: speed_encoder, T_body_sensor: {translation: [-0.7, 0, 0.3]}}
  - {topic: /joint_states, id: wheels, type: wheel_encoders, joints: [fl, fr, rl, rr]}
  - {topic: /joint_states, id: steering, type: steering_encoder, joint: steer}
static_transforms:
  - {parent: base_link, child: gps, T_parent_child: {translation: [0.25, 0, 1.5]}}
)");
  const RosbagImportResult r = ImportRosbag(b.bag(), LoadRosTopicMap(b.map()), b.log());
  ASSERT_FALSE(r.error.has_value()) << *r.error;
  ASSERT_EQ(r.unmapped.size(), 1u);
  EXPECT_EQ(r.unmapped[0].topic, "/ignored");
  ASSERT_EQ(r.streams.size(), 7u);
  EXPECT_EQ(r.streams[0].arrivals_at_stamp, 1u);
  EXPECT_EQ(r.streams[1].skipped, 1u);  // the NO_FIX without position
  EXPECT_EQ(r.streams[5].skipped, 5u);  // the arm's messages
  EXPECT_EQ(r.streams[6].skipped, 5u);

  std::optional<std::string> error;
  const std::vector<Measurement> log = testing::ReadLog(b.log(), &error);
  ASSERT_FALSE(error.has_value()) << *error;
  const auto imu = OfSensor<ImuSample>(log, "imu");
  ASSERT_EQ(imu.size(), 5u);
  EXPECT_EQ(imu[3].header.stamp_ns, kT0 + 30 * kMs);
  EXPECT_EQ(imu[3].header.arrival_ns, kT0 + 32 * kMs);
  EXPECT_EQ(imu[2].header.arrival_ns, imu[2].header.stamp_ns);  // received 1 ms before its stamp
  EXPECT_EQ(imu[4].gyro, Vec3(0.04, 0.0, -0.3));
  EXPECT_EQ(imu[4].accel, Vec3(0.0, 0.0, 9.81));

  const auto gnss = OfSensor<GnssFix>(log, "gnss");
  ASSERT_EQ(gnss.size(), 4u);
  EXPECT_EQ(gnss[0].status, GnssFixStatus::kSingle);
  EXPECT_EQ(gnss[1].status, GnssFixStatus::kRtkFixed);  // GBAS, sigma 1 cm
  EXPECT_EQ(gnss[2].status, GnssFixStatus::kRtkFloat);  // GBAS, sigma 0.5 m
  EXPECT_EQ(gnss[3].status, GnssFixStatus::kSingle);    // SBAS
  EXPECT_EQ(gnss[0].latitude_deg, 48.0 + 1e-6);
  EXPECT_EQ(gnss[2].covariance_enu(0, 1), 0.025);
  EXPECT_EQ(gnss[2].covariance_enu(2, 2), 1.0);

  const auto odom = OfSensor<BodyVelocity>(log, "wheel_odom");
  ASSERT_EQ(odom.size(), 5u);
  EXPECT_EQ(odom[1].velocity, Vec3(2.5, 0.0, 0.0));
  EXPECT_EQ(odom[1].angular_velocity, Vec3(0.0, 0.0, 0.2));
  EXPECT_EQ(odom[1].covariance(2, 2), 1e6);
  EXPECT_EQ(odom[1].covariance(5, 5), 1e-2);
  const auto cmd = OfSensor<BodyVelocity>(log, "cmd");
  ASSERT_EQ(cmd.size(), 5u);
  EXPECT_DOUBLE_EQ(cmd[0].covariance(1, 1), 0.04);
  EXPECT_EQ(cmd[0].covariance(5, 5), 9.0);
  EXPECT_EQ(cmd[0].covariance(0, 1), 0.0);

  const auto speed = OfSensor<VehicleSpeed>(log, "speed");
  ASSERT_EQ(speed.size(), 5u);
  EXPECT_EQ(speed[2].speed_mps, 1.25);
  const auto wheels = OfSensor<WheelSpeeds>(log, "wheels");
  ASSERT_EQ(wheels.size(), 5u);
  EXPECT_EQ(wheels[0].omega_radps, (std::array<double, 4>{1.0, 2.0, 3.0, 4.0}));
  const auto steering = OfSensor<SteeringAngle>(log, "steering");
  ASSERT_EQ(steering.size(), 5u);
  EXPECT_EQ(steering[3].angle_rad, 0.03);

  const LogManifest manifest = ReadLogManifest(b.log() / "log.yaml");
  EXPECT_EQ(manifest.scenario, "test.bag");
  ASSERT_TRUE(manifest.origin.has_value());
  EXPECT_EQ(manifest.origin->latitude_deg, 48.0);

  // Mounts: the IMU through base_link -> chassis (yawed 90 deg) -> imu_link; the map's static
  // transform replaces /tf_static's for gps; the speed sensor's is the map's T_body_sensor;
  // frames a topic does not name (JointState) are the base frame.
  const auto mounts = MountsOf(b.log());
  ASSERT_EQ(mounts.size(), 7u);
  EXPECT_EQ(mounts.at("imu").type, "imu");
  EXPECT_TRUE(mounts.at("imu").T_body_sensor.translation().isApprox(Vec3(1.0, 0.0, 0.5), 1e-15));
  EXPECT_LT(mounts.at("imu").T_body_sensor.rotation().angularDistance(q_base_chassis), 1e-12);
  EXPECT_EQ(mounts.at("gnss").T_body_sensor.translation(), Vec3(0.25, 0.0, 1.5));
  EXPECT_EQ(mounts.at("speed").T_body_sensor.translation(), Vec3(-0.7, 0.0, 0.3));
  EXPECT_EQ(mounts.at("wheels").T_body_sensor.translation(), Vec3::Zero());
  EXPECT_EQ(mounts.at("wheel_odom").type, "body_velocity");
  EXPECT_EQ(mounts.at("steering").type, "steering_encoder");
  // Latencies: the largest receive - stamp (never negative), or the map's.
  EXPECT_EQ(*mounts.at("imu").latency_s, 0.002);
  EXPECT_EQ(*mounts.at("gnss").latency_s, 0.2);
  EXPECT_EQ(*mounts.at("wheel_odom").latency_s, 0.005);
  EXPECT_EQ(r.notes.size(), 2u);  // wheels and steering: JointStates without frame_id
}

TEST(RosbagImport, ReadsThePointCloudLayoutsOfCommonDrivers) {
  using sensor_msgs::PointField;
  TestBag b("clouds");
  // Ouster-like: padded float32 xyz, uint32 t in ns after the stamp, organised 2 x 2 with a
  // NaN (no return).
  sensor_msgs::PointCloud2 ouster;
  ouster.header = RosHeader(kT0, "os_lidar");
  ouster.fields = {testing::Field("x", 0, PointField::FLOAT32),
                   testing::Field("y", 4, PointField::FLOAT32),
                   testing::Field("z", 8, PointField::FLOAT32),
                   testing::Field("intensity", 16, PointField::FLOAT32),
                   testing::Field("t", 20, PointField::UINT32),
                   testing::Field("ring", 26, PointField::UINT8)};
  ouster.point_step = 48;
  ouster.width = 2;
  ouster.height = 2;
  ouster.row_step = 96;
  ouster.data.resize(192);
  for (std::size_t i = 0; i < 4; ++i) {
    testing::Put(&ouster, i, 0, i == 1 ? std::numeric_limits<float>::quiet_NaN() : 1.5f * i);
    testing::Put(&ouster, i, 4, -2.0f);
    testing::Put(&ouster, i, 8, 0.25f);
    testing::Put(&ouster, i, 16, 7.0f);
    testing::Put(&ouster, i, 20, static_cast<std::uint32_t>(25'000'000 * i));
    testing::Put(&ouster, i, 26, static_cast<std::uint8_t>(i));
  }
  b.Write("/ouster/points", kT0 + 120 * kMs, ouster);

  // Velodyne-like: float32 "time" relative to a stamp at the END of the sweep (negative).
  sensor_msgs::PointCloud2 velodyne;
  velodyne.header = RosHeader(kT0, "velodyne");
  velodyne.fields = {testing::Field("x", 0, PointField::FLOAT32),
                     testing::Field("y", 4, PointField::FLOAT32),
                     testing::Field("z", 8, PointField::FLOAT32),
                     testing::Field("intensity", 12, PointField::FLOAT32),
                     testing::Field("ring", 16, PointField::UINT16),
                     testing::Field("time", 18, PointField::FLOAT32)};
  velodyne.point_step = 22;
  velodyne.width = 3;
  velodyne.height = 1;
  velodyne.row_step = 66;
  velodyne.data.resize(66);
  const float times[3] = {-0.1f, -0.05f, 0.0f};
  for (std::size_t i = 0; i < 3; ++i) {
    testing::Put(&velodyne, i, 0, 1.0f);
    testing::Put(&velodyne, i, 16, static_cast<std::uint16_t>(15));
    testing::Put(&velodyne, i, 18, times[i]);
  }
  b.Write("/velodyne_points", kT0 + 10 * kMs, velodyne);

  // Hesai-like: float64 xyz (rounded to float) and absolute float64 "timestamp" in seconds.
  sensor_msgs::PointCloud2 hesai;
  hesai.header = RosHeader(kT0, "hesai");
  hesai.fields = {testing::Field("x", 0, PointField::FLOAT64),
                  testing::Field("y", 8, PointField::FLOAT64),
                  testing::Field("z", 16, PointField::FLOAT64),
                  testing::Field("timestamp", 24, PointField::FLOAT64)};
  hesai.point_step = 32;
  hesai.width = 2;
  hesai.height = 1;
  hesai.row_step = 64;
  hesai.data.resize(64);
  for (std::size_t i = 0; i < 2; ++i) {
    testing::Put(&hesai, i, 0, 0.1);
    testing::Put(&hesai, i, 8, 0.2);
    testing::Put(&hesai, i, 16, 0.3);
    testing::Put(&hesai, i, 24, ToSeconds(kT0) + 0.0625 * static_cast<double>(i));
  }
  b.Write("/hesai/pandar", kT0 + 150 * kMs, hesai);
  b.Close();
  b.WriteMap(R"(topics:
  - {topic: /ouster/points, id: ouster, type: lidar}
  - {topic: /velodyne_points, id: velodyne, type: lidar}
  - {topic: /hesai/pandar, id: hesai, type: lidar}
static_transforms:
  - {parent: base_link, child: os_lidar, T_parent_child: {translation: [0, 0, 2]}}
  - {parent: base_link, child: velodyne, T_parent_child: {translation: [0, 0, 2]}}
  - {parent: base_link, child: hesai, T_parent_child: {translation: [0, 0, 2]}}
)");
  const RosbagImportResult r = ImportRosbag(b.bag(), LoadRosTopicMap(b.map()), b.log());
  ASSERT_FALSE(r.error.has_value()) << *r.error;
  EXPECT_EQ(r.streams[0].skipped, 1u);
  EXPECT_EQ(r.streams[0].time_field, "t");
  EXPECT_EQ(r.streams[1].time_field, "time");
  EXPECT_EQ(r.streams[2].time_field, "timestamp");
  const std::vector<Measurement> log = testing::ReadLog(b.log());

  const auto ouster_scans = OfSensor<LidarScan>(log, "ouster");
  ASSERT_EQ(ouster_scans.size(), 1u);
  const std::vector<LidarPoint>& o = *ouster_scans[0].points;
  ASSERT_EQ(o.size(), 3u);
  EXPECT_EQ(ouster_scans[0].header.stamp_ns, kT0);
  EXPECT_EQ(o[2].x, 4.5f);
  EXPECT_EQ(o[2].t, 0.075f);
  EXPECT_EQ(o[2].ring, 3);
  EXPECT_EQ(o[2].intensity, 7.0f);

  const auto velodyne_scans = OfSensor<LidarScan>(log, "velodyne");
  ASSERT_EQ(velodyne_scans.size(), 1u);
  const std::vector<LidarPoint>& v = *velodyne_scans[0].points;
  // The stamp moves to the first point; times count from there.
  EXPECT_NEAR(static_cast<double>(velodyne_scans[0].header.stamp_ns - kT0), -1e8, 3.0);
  EXPECT_GE(v[0].t, 0.0f);
  EXPECT_LT(v[0].t, 1e-8f);
  EXPECT_NEAR(v[2].t, 0.1, 1e-7);
  EXPECT_EQ(v[1].ring, 15);

  const auto hesai_scans = OfSensor<LidarScan>(log, "hesai");
  const std::vector<LidarPoint>& h = *hesai_scans.at(0).points;
  EXPECT_EQ(h[0].x, 0.1f);
  EXPECT_EQ(h[0].t, 0.0f);
  EXPECT_NEAR(h[1].t, 0.0625, 1e-6);  // absolute seconds as doubles: ~0.2 us resolution
  EXPECT_EQ(h[1].intensity, 0.0f);
  // Latency after the last point: hesai 150 ms after the stamp, last point at 62.5 ms.
  EXPECT_NEAR(*MountsOf(b.log()).at("hesai").latency_s, 0.0875, 1e-6);
}

TEST(RosbagImport, SuggestsATopicMapThatLoads) {
  TestBag b("suggest");
  b.StaticTransform("base_link", "imu_link", Vec3(0, 0, 0.3), Quat::Identity());
  for (int k = 1; k <= 3; ++k) {
    sensor_msgs::Imu imu;
    imu.header = RosHeader(kT0 + k * 10 * kMs, "imu_link");
    b.Write("/imu/data", kT0 + k * 10 * kMs, imu);
    geometry_msgs::TwistStamped twist;
    twist.header = RosHeader(kT0 + k * 100 * kMs, "base_link");
    b.Write("/cmd_vel_stamped", kT0 + k * 100 * kMs, twist);
    sensor_msgs::JointState joints;
    joints.header = RosHeader(kT0 + k * 20 * kMs, "");
    b.Write("/joint_states", kT0 + k * 20 * kMs, joints);
  }
  b.Write("/diagnostics", kT0, tf2_msgs::TFMessage());
  b.Close();
  const RosbagSummary summary = SummarizeRosbag(b.bag());
  ASSERT_EQ(summary.topics.size(), 5u);
  EXPECT_EQ(summary.begin_ns, 1);
  EXPECT_EQ(summary.topics[2].topic, "/imu/data");
  EXPECT_EQ(summary.topics[2].messages, 3u);
  EXPECT_NEAR(summary.topics[2].rate_hz, 100.0, 1e-9);
  EXPECT_EQ(summary.topics[2].frame_id, "imu_link");
  ASSERT_EQ(summary.static_transforms.size(), 1u);
  EXPECT_EQ(summary.static_transforms[0].child, "imu_link");

  const std::string yaml = SuggestTopicMap(summary);
  EXPECT_NE(yaml.find("#   /diagnostics (tf2_msgs/TFMessage"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("# - topic: \"/joint_states\""), std::string::npos) << yaml;
  const RosTopicMap map = ParseRosTopicMap(YamlNode::LoadString(yaml, "suggested.yaml"));
  ASSERT_EQ(map.topics.size(), 2u);
  EXPECT_EQ(map.topics[0].id, "cmd_vel_stamped");
  EXPECT_EQ(map.topics[0].kind, RosTopicKind::kBodyVelocity);
  EXPECT_TRUE(map.topics[0].twist_sigma.has_value());
  EXPECT_EQ(map.topics[1].id, "imu_data");
  EXPECT_EQ(map.topics[1].kind, RosTopicKind::kImu);
  const RosbagImportResult r = ImportRosbag(b.bag(), map, b.log());
  EXPECT_FALSE(r.error.has_value()) << *r.error;
}

}  // namespace
}  // namespace statebench::sensors
