// Bad bags and bad topic maps: a clear error naming the bag, topic and message index (or the
// map's file:line), and the log keeps what was converted before the error.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "ros1_test_bag.hpp"
#include "sensors/rosbag_import.hpp"
#include "sensors/sensor_mounts.hpp"

namespace statebench::sensors {
namespace {

using testing::RosHeader;
using testing::TestBag;

constexpr TimeNs kMs = kNsPerMillisecond;
constexpr TimeNs kT0 = 1'600'000'000 * kNsPerSecond;

// Five IMU messages 10 ms apart in frame imu_link; `edit` may spoil message k.
template <typename Edit>
void WriteImu(TestBag& b, Edit edit) {
  b.StaticTransform("base_link", "imu_link", Vec3(0, 0, 0.5), Quat::Identity());
  for (int k = 0; k < 5; ++k) {
    sensor_msgs::Imu imu;
    imu.header = RosHeader(kT0 + k * 10 * kMs, "imu_link");
    imu.linear_acceleration.z = 9.81;
    edit(k, imu);
    b.Write("/imu", kT0 + k * 10 * kMs + kMs, imu);
  }
  b.Close();
  b.WriteMap("topics:\n  - {topic: /imu, id: imu, type: imu}\n");
}

std::string ThrownBy(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string ImportError(const TestBag& b) {
  const RosbagImportResult r = ImportRosbag(b.bag(), LoadRosTopicMap(b.map()), b.log());
  return r.error.value_or("(no error)");
}

TEST(RosbagBadInput, NotABag) {
  TestBag b("not_a_bag");
  b.Close();
  std::ofstream(b.dir() / "text.bag") << "hello\n";
  b.WriteMap("topics:\n  - {topic: /imu, id: imu, type: imu}\n");
  const std::string e = ThrownBy([&] { SummarizeRosbag(b.dir() / "text.bag"); });
  EXPECT_NE(e.find("text.bag: not a readable ROS1 bag"), std::string::npos) << e;
  const std::string missing =
      ThrownBy([&] { ImportRosbag(b.dir() / "missing.bag", LoadRosTopicMap(b.map()), b.log()); });
  EXPECT_NE(missing.find("missing.bag: no such bag file"), std::string::npos) << missing;
  EXPECT_FALSE(std::filesystem::exists(b.log()));
}

TEST(RosbagBadInput, MapProblemsNameTheMapLineBeforeWritingAnything) {
  TestBag b("map");
  WriteImu(b, [](int, sensor_msgs::Imu&) {});
  const auto import_with = [&](const std::string& yaml) {
    b.WriteMap(yaml);
    return ThrownBy([&] { ImportRosbag(b.bag(), LoadRosTopicMap(b.map()), b.log()); });
  };
  std::string e = import_with(
      "topics:\n  - {topic: /imu, id: imu, type: imu}\n"
      "  - {topic: /gps/fix, id: gnss, type: gnss}\n");
  EXPECT_NE(e.find("map.yaml:3:5: topic '/gps/fix' is not in"), std::string::npos) << e;
  EXPECT_NE(e.find("(its topics: /imu, /tf_static)"), std::string::npos) << e;
  e = import_with("topics:\n  - {topic: /imu, id: imu, type: lidar}\n");
  EXPECT_NE(e.find("map.yaml:2:5: topic '/imu' holds sensor_msgs/Imu messages, which cannot "
                   "become a sensor of type 'lidar'"),
            std::string::npos)
      << e;
  e = import_with(
      "topics:\n  - {topic: /imu, id: imu, type: imu, twist_sigma: [1, 1, 1, 1, 1, 1]}\n");
  EXPECT_NE(e.find("field 'topics[0].twist_sigma': not an option of a topic of type 'imu'"),
            std::string::npos)
      << e;
  e = import_with("topics:\n  - {topic: /imu, id: a/b, type: imu}\n");
  EXPECT_NE(e.find("map.yaml:2:23: field 'topics[0].id': sensor id 'a/b' cannot name a file"),
            std::string::npos)
      << e;
  e = import_with("topics:\n  - {topic: /imu, id: imu, type: radar}\n");
  EXPECT_NE(e.find("unknown type 'radar'"), std::string::npos) << e;
  e = import_with(
      "topics:\n  - {topic: /imu, id: imu, type: imu}\n  - {topic: /imu, id: imu, "
      "type: imu}\n");
  EXPECT_NE(e.find("field 'topics[1].id': duplicate sensor id 'imu'"), std::string::npos) << e;
  e = import_with("topic:\n  - {topic: /imu, id: imu, type: imu}\n");
  EXPECT_NE(e.find("field 'topic': unknown field"), std::string::npos) << e;
  EXPECT_FALSE(std::filesystem::exists(b.log()));
}

TEST(RosbagBadInput, ANonFiniteValueStopsTheImportAndKeepsWhatCameBefore) {
  TestBag b("nan");
  WriteImu(b, [](int k, sensor_msgs::Imu& imu) {
    if (k == 3) imu.angular_velocity.y = std::numeric_limits<double>::quiet_NaN();
  });
  const std::string e = ImportError(b);
  EXPECT_NE(e.find("test.bag: topic '/imu' message 3 (sensor_msgs/Imu, bag time "
                   "1600000000.031000000 s): angular_velocity is not finite"),
            std::string::npos)
      << e;
  std::optional<std::string> read_error;
  const std::vector<Measurement> log = testing::ReadLog(b.log(), &read_error);
  EXPECT_FALSE(read_error.has_value());
  EXPECT_EQ(log.size(), 3u);
  EXPECT_EQ(ReadSensorMounts(b.log() / "setup.yaml").size(), 1u);  // setup written too
}

TEST(RosbagBadInput, StampsThatDoNotIncrease) {
  TestBag b("stamps");
  WriteImu(b, [](int k, sensor_msgs::Imu& imu) {
    if (k == 4) imu.header.stamp = testing::Ros(kT0 + 30 * kMs);
  });
  const std::string e = ImportError(b);
  EXPECT_NE(e.find("topic '/imu' message 4"), std::string::npos) << e;
  EXPECT_NE(e.find("is not after the previous message's"), std::string::npos) << e;
  EXPECT_EQ(testing::ReadLog(b.log()).size(), 4u);
}

TEST(RosbagBadInput, AFrameThatChanges) {
  TestBag b("frame");
  WriteImu(b, [](int k, sensor_msgs::Imu& imu) {
    if (k == 1) imu.header.frame_id = "imu2";
  });
  const std::string e = ImportError(b);
  EXPECT_NE(e.find("message 1 (sensor_msgs/Imu"), std::string::npos) << e;
  EXPECT_NE(e.find("frame_id 'imu2' differs from the topic's earlier 'imu_link'"),
            std::string::npos)
      << e;
}

TEST(RosbagBadInput, AFrameWithoutStaticTransform) {
  TestBag b("no_tf");
  sensor_msgs::Imu imu;
  imu.header = RosHeader(kT0, "imu_link");
  b.Write("/imu", kT0, imu);
  b.Close();
  b.WriteMap("base_frame: base_footprint\ntopics:\n  - {topic: /imu, id: imu, type: imu}\n");
  const std::string e = ImportError(b);
  EXPECT_NE(e.find("topic '/imu' (sensor 'imu'): no static transform connects the base frame "
                   "'base_footprint' to its frame 'imu_link'"),
            std::string::npos)
      << e;
  EXPECT_EQ(testing::ReadLog(b.log()).size(), 1u);  // the measurements are kept
  EXPECT_TRUE(ReadSensorMounts(b.log() / "setup.yaml").empty());
}

TEST(RosbagBadInput, ConversionsThatNeedTheMap) {
  TestBag b("needs_map");
  sensor_msgs::NavSatFix fix;
  fix.header = RosHeader(kT0, "base_link");
  fix.latitude = 48.0;
  fix.position_covariance_type = sensor_msgs::NavSatFix::COVARIANCE_TYPE_UNKNOWN;
  b.Write("/fix", kT0, fix);
  geometry_msgs::TwistStamped twist;
  twist.header = RosHeader(kT0, "base_link");
  b.Write("/twist", kT0, twist);
  nav_msgs::Odometry odom;  // all-zero twist covariance: unknown
  odom.header = RosHeader(kT0, "odom");
  odom.child_frame_id = "base_link";
  b.Write("/odom", kT0, odom);
  b.Close();

  b.WriteMap("topics:\n  - {topic: /fix, id: gnss, type: gnss}\n");
  std::string e = ImportError(b);
  EXPECT_NE(e.find("topic '/fix' message 0"), std::string::npos) << e;
  EXPECT_NE(e.find("position_covariance_type is UNKNOWN (0): give position_sigma_m"),
            std::string::npos)
      << e;
  std::filesystem::remove_all(b.log());
  b.WriteMap("topics:\n  - {topic: /fix, id: gnss, type: gnss, position_sigma_m: [1, 2, 3]}\n");
  EXPECT_EQ(ImportError(b), "(no error)");
  const auto fixes = testing::OfSensor<GnssFix>(testing::ReadLog(b.log()), "gnss");
  ASSERT_EQ(fixes.size(), 1u);
  EXPECT_EQ(fixes[0].covariance_enu.diagonal(), Vec3(1, 4, 9));
  EXPECT_EQ(fixes[0].status, GnssFixStatus::kSingle);

  std::filesystem::remove_all(b.log());
  b.WriteMap("topics:\n  - {topic: /twist, id: v, type: body_velocity}\n");
  e = ThrownBy([&] { ImportRosbag(b.bag(), LoadRosTopicMap(b.map()), b.log()); });
  EXPECT_NE(e.find("map.yaml:2:5: topic '/twist' (geometry_msgs/TwistStamped) carries no "
                   "covariance: give twist_sigma"),
            std::string::npos)
      << e;
  b.WriteMap("topics:\n  - {topic: /odom, id: v, type: body_velocity}\n");
  e = ImportError(b);
  EXPECT_NE(e.find("topic '/odom' message 0 (nav_msgs/Odometry"), std::string::npos) << e;
  EXPECT_NE(e.find("twist covariance is all zero (unknown): give twist_sigma"), std::string::npos)
      << e;
}

TEST(RosbagBadInput, APointCloudShorterThanItsLayout) {
  TestBag b("cloud");
  sensor_msgs::PointCloud2 cloud;
  cloud.header = RosHeader(kT0, "base_link");
  cloud.fields = {testing::Field("x", 0, sensor_msgs::PointField::FLOAT32),
                  testing::Field("y", 4, sensor_msgs::PointField::FLOAT32),
                  testing::Field("z", 8, sensor_msgs::PointField::FLOAT32)};
  cloud.point_step = 12;
  cloud.width = 10;
  cloud.height = 1;
  cloud.row_step = 120;
  cloud.data.resize(100);
  b.Write("/points", kT0, cloud);
  cloud.fields[2].datatype = sensor_msgs::PointField::UINT16;
  cloud.data.resize(120);
  cloud.header.stamp = testing::Ros(kT0 + 100 * kMs);
  b.Write("/points2", kT0, cloud);
  b.Close();
  b.WriteMap("topics:\n  - {topic: /points, id: lidar, type: lidar}\n");
  std::string e = ImportError(b);
  EXPECT_NE(e.find("topic '/points' message 0 (sensor_msgs/PointCloud2, bag time "
                   "1600000000.000000000 s): data holds 100 bytes, height 1 x row_step 120 need "
                   "120"),
            std::string::npos)
      << e;
  std::filesystem::remove_all(b.log());
  b.WriteMap("topics:\n  - {topic: /points2, id: lidar, type: lidar}\n");
  e = ImportError(b);
  EXPECT_NE(e.find("field 'z' is not float32 or float64"), std::string::npos) << e;
}

}  // namespace
}  // namespace statebench::sensors
