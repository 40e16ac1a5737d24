// A recorded log exported to a ROS1 bag and imported back (with the topic map the export returns)
// is the same log: every measurement of every exported type bit for bit (values drawn as random
// bit patterns where the messages allow any), the setup's mounts and latencies, the manifest's
// origin and scenario; a time offset and its opposite cancel. Dual-antenna headings have no ROS
// message: the export reports them and leaves them out.
#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "core/error.hpp"
#include "log_test_fixtures.hpp"
#include "measurement_bytes.hpp"
#include "sensors/rosbag_export.hpp"
#include "sensors/rosbag_import.hpp"
#include "sensors/sensor_mounts.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;
using statebench::testing::MeasurementBytes;

// A diagonal-dominant covariance: positive diagonal in [lo, hi), off-diagonals of any sign.
template <int N>
Eigen::Matrix<double, N, N> Covariance(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> diag(lo, hi);
  std::uniform_real_distribution<double> off(-0.1 * lo, 0.1 * lo);
  Eigen::Matrix<double, N, N> c;
  for (int r = 0; r < N; ++r) {
    for (int k = 0; k < N; ++k) c(r, k) = r == k ? diag(rng) : off(rng);
  }
  return c;
}

// Two seconds of every type the export writes, plus a dual-antenna heading, with valid
// covariances, GNSS statuses that the covariance tells apart (RTK fixed sigma below 0.1 m),
// lidar times in [0, 0.1) s.
std::vector<Measurement> ValidStream(std::uint64_t seed) {
  testing::AnyBits bits(seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> t_dist(0.f, 0.1f);
  std::vector<Measurement> out;
  const auto header = [](const char* id, TimeNs t, TimeNs latency_ms) {
    return MeasurementHeader{id, t, t + latency_ms * kNsPerMillisecond};
  };
  for (TimeNs t = 0; t <= 2 * kNsPerSecond; t += 10 * kNsPerMillisecond) {
    out.push_back(ImuSample{header("imu", t, 2), Vec3(bits.Double(), bits.Double(), -0.0),
                            Vec3(bits.Double(), bits.Double(), bits.Double())});
    if (t % (20 * kNsPerMillisecond) == 0 && t > 0) {
      WheelSpeeds w{header("wheels", t, 10)};
      for (double& o : w.omega_radps) o = bits.Double();
      out.push_back(w);
      out.push_back(VehicleSpeed{header("speed", t, 10), bits.Double()});
      out.push_back(SteeringAngle{header("steering", t, 0), bits.Double()});
    }
    if (t % (50 * kNsPerMillisecond) == 0) {
      BodyVelocity b{header("radar", t, 30)};
      b.velocity = Vec3(bits.Double(), bits.Double(), bits.Double());
      b.angular_velocity = Vec3(bits.Double(), bits.Double(), bits.Double());
      b.covariance = Covariance<6>(rng, 1e-4, 1e6);
      out.push_back(b);
    }
    if (t % (100 * kNsPerMillisecond) == 0) {
      const int k = static_cast<int>(t / (100 * kNsPerMillisecond));
      GnssFix f;
      f.header = header("gnss", t, 100);
      f.latitude_deg = std::fmod(bits.Double(), 90.0);
      f.longitude_deg = std::fmod(bits.Double(), 180.0);
      f.altitude_m = bits.Double();
      f.status = static_cast<GnssFixStatus>(k % 4);
      const bool fixed = f.status == GnssFixStatus::kRtkFixed;
      f.covariance_enu = fixed ? Covariance<3>(rng, 1e-6, 9e-3) : Covariance<3>(rng, 0.011, 9.0);
      if (k % 3 != 2) {  // a Doppler velocity at two fixes of three (the first one too)
        std::uniform_real_distribution<double> sigma(0.01, 1.0);
        f.velocity = GnssVelocity{Vec3(bits.Double(), bits.Double(), bits.Double()),
                                  Vec3(sigma(rng), sigma(rng), sigma(rng))};
      }
      out.push_back(f);
      out.push_back(DualAntennaHeading{header("heading", t, 100), 0.1, 0.0, 0.01, 0.02});
      LidarScan scan{header("lidar", t, 120), nullptr};
      auto points = std::make_shared<std::vector<LidarPoint>>();
      for (int i = 0; i < (k == 3 ? 0 : 200); ++i) {
        points->push_back(LidarPoint{bits.Float(), bits.Float(), bits.Float(), bits.Float(),
                                     t_dist(rng), bits.Ring()});
      }
      scan.points = points;
      out.push_back(scan);
    }
  }
  std::stable_sort(out.begin(), out.end(), ArrivesBefore);
  return out;
}

constexpr const char* kSetup = R"(name: round_trip
sensors:
  - {type: imu, id: imu, T_body_sensor: {translation: [0.1, -0.2, 0.5], rpy_deg: [1, -2, 93]}, latency_s: 0.002}
  - {type: gnss, id: gnss, T_body_sensor: {translation: [0.45, 0.0, 1.5]}, latency_s: 0.1}
  - {type: wheel_encoders, id: wheels, T_body_sensor: {translation: [0, 0, 0]}, latency_s: 0.01}
  - {type: speed_encoder, id: speed, T_body_sensor: {translation: [-0.76, 0, 0.27]}, latency_s: 0.01}
  - {type: steering_encoder, id: steering, T_body_sensor: {translation: [0.93, 0, 0.27]}, latency_s: 0}
  - {type: body_velocity, id: radar, T_body_sensor: {translation: [2, 0, 0.5], rpy_deg: [0, 0, 180]}, latency_s: 0.03}
  - {type: lidar, id: lidar, T_body_sensor: {translation: [-0.15, 0, 1.62], rpy_deg: [0, 10, 0]}, latency_s: 0.02}
)";

std::vector<Measurement> ReadBagTestLog(const fs::path& dir) {
  LogReader reader(dir);
  std::vector<Measurement> out;
  while (auto m = reader.Next()) out.push_back(std::move(*m));
  EXPECT_FALSE(reader.error().has_value()) << *reader.error();
  return out;
}

void WriteBagTestLog(const fs::path& dir, const std::vector<Measurement>& stream) {
  LogWriterOptions options;
  options.scenario = "round \"trip\"";
  options.origin = GeodeticPoint{48.7846, 2.136, 130.25};
  options.setup_yaml = kSetup;
  LogWriter writer(dir, options);
  for (const Measurement& m : stream) writer.Write(m);
  writer.Close();
}

TEST(RosbagRoundTrip, ExportThenImportGivesTheSameLog) {
  testing::TempLogDir dir("rosbag_round_trip");
  const std::vector<Measurement> written = ValidStream(5);
  WriteBagTestLog(dir.path() / "log", written);

  const RosbagExportResult exported = ExportRosbag(dir.path() / "log", dir.path() / "log.bag");
  ASSERT_FALSE(exported.error.has_value()) << *exported.error;
  EXPECT_EQ(exported.static_transforms, 7u);
  std::map<std::string, RosbagExportStream> by_id;
  for (const RosbagExportStream& s : exported.streams) by_id[s.id] = s;
  EXPECT_EQ(by_id.at("heading").topic, "");  // no ROS message for a baseline heading
  EXPECT_EQ(by_id.at("imu").datatype, "sensor_msgs/Imu");
  EXPECT_EQ(by_id.at("radar").datatype, "geometry_msgs/TwistWithCovarianceStamped");
  EXPECT_EQ(by_id.at("steering").datatype, "sensor_msgs/JointState");
  std::size_t velocities = 0;
  for (const RosbagExportStream& s : exported.streams) {
    if (s.topic != "/gnss/vel") continue;
    EXPECT_EQ(s.datatype, "geometry_msgs/TwistWithCovarianceStamped");
    velocities = s.count;
  }
  EXPECT_EQ(velocities, 14u);  // 21 fixes, every third without

  const RosbagImportResult imported =
      ImportRosbag(dir.path() / "log.bag", exported.topic_map, dir.path() / "back");
  ASSERT_FALSE(imported.error.has_value()) << *imported.error;
  EXPECT_TRUE(imported.unmapped.empty());
  for (const RosbagImportStream& s : imported.streams) {
    if (s.kind != RosTopicKind::kGnssVelocity) continue;
    EXPECT_EQ(s.count, 14u);  // each joined to its fix
    EXPECT_EQ(s.skipped, 0u);
  }

  std::vector<Measurement> expected;
  for (const Measurement& m : written) {
    if (!std::holds_alternative<DualAntennaHeading>(m)) expected.push_back(m);
  }
  const std::vector<Measurement> back = ReadBagTestLog(dir.path() / "back");
  ASSERT_EQ(back.size(), expected.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    ASSERT_EQ(MeasurementBytes(back[i]), MeasurementBytes(expected[i])) << "measurement " << i;
  }

  const LogManifest manifest = ReadLogManifest(dir.path() / "back" / "log.yaml");
  EXPECT_EQ(manifest.scenario, "round \"trip\"");
  ASSERT_TRUE(manifest.origin.has_value());
  EXPECT_EQ(manifest.origin->altitude_m, 130.25);

  // Mounts through /tf_static: translations exact, rotations to rounding; latencies from the
  // delays (the lidar's counted after its last point, so at most the setup's).
  const std::vector<SensorMount> original = ReadSensorMounts(dir.path() / "log" / "setup.yaml");
  const std::vector<SensorMount> mounts = ReadSensorMounts(dir.path() / "back" / "setup.yaml");
  ASSERT_EQ(mounts.size(), original.size());
  std::map<std::string, SensorMount> mount_of;
  for (const SensorMount& m : mounts) mount_of[m.id] = m;
  for (const SensorMount& o : original) {
    const SensorMount& m = mount_of.at(o.id);
    EXPECT_EQ(m.type, o.type);
    EXPECT_EQ(m.T_body_sensor.translation(), o.T_body_sensor.translation()) << o.id;
    EXPECT_LT(m.T_body_sensor.rotation().angularDistance(o.T_body_sensor.rotation()), 1e-15);
    ASSERT_TRUE(m.latency_s.has_value());
    if (o.type == "lidar") {
      EXPECT_GT(*m.latency_s, *o.latency_s);  // 0.12 s after a stamp, points end before 0.1 s
      EXPECT_LT(*m.latency_s, *o.latency_s + 0.1);
    } else {
      EXPECT_EQ(*m.latency_s, *o.latency_s) << o.id;
    }
  }
}

TEST(RosbagRoundTrip, TimeOffsetAndItsOppositeCancel) {
  testing::TempLogDir dir("rosbag_offset");
  std::vector<Measurement> written = ValidStream(8);
  WriteBagTestLog(dir.path() / "log", written);
  RosbagExportOptions out_options;
  out_options.time_offset_ns = 1'700'000'000 * kNsPerSecond + 123;
  const RosbagExportResult exported =
      ExportRosbag(dir.path() / "log", dir.path() / "log.bag", out_options);
  ASSERT_FALSE(exported.error.has_value()) << *exported.error;
  const RosbagSummary summary = SummarizeRosbag(dir.path() / "log.bag");
  EXPECT_EQ(summary.begin_ns, out_options.time_offset_ns + 2 * kNsPerMillisecond);
  RosbagImportOptions in_options;
  in_options.time_offset_ns = -out_options.time_offset_ns;
  const RosbagImportResult imported =
      ImportRosbag(dir.path() / "log.bag", exported.topic_map, dir.path() / "back", in_options);
  ASSERT_FALSE(imported.error.has_value()) << *imported.error;
  std::erase_if(written,
                [](const Measurement& m) { return std::holds_alternative<DualAntennaHeading>(m); });
  const std::vector<Measurement> back = ReadBagTestLog(dir.path() / "back");
  ASSERT_EQ(back.size(), written.size());
  for (std::size_t i = 0; i < back.size(); ++i) {
    ASSERT_EQ(MeasurementBytes(back[i]), MeasurementBytes(written[i])) << "measurement " << i;
  }
}

TEST(RosbagRoundTrip, ExportRefusesWhatABagCannotHold) {
  testing::TempLogDir dir("rosbag_export_errors");
  // A zero-latency sample at t = 0 arrives at 0, before the earliest ROS1 bag time (1 ns).
  WriteBagTestLog(dir.path() / "log", {ImuSample{{"imu", 0, 0}, Vec3::Zero(), Vec3::Zero()},
                                ImuSample{{"imu", 10, 10}, Vec3::Zero(), Vec3::Zero()}});
  const RosbagExportResult r = ExportRosbag(dir.path() / "log", dir.path() / "a.bag");
  ASSERT_TRUE(r.error.has_value());
  EXPECT_NE(r.error->find("sensor 'imu' stamp 0 ns"), std::string::npos) << *r.error;
  EXPECT_NE(r.error->find("time offset"), std::string::npos) << *r.error;
  // The bag exists now: a second export to it is refused before anything is written.
  EXPECT_THROW(ExportRosbag(dir.path() / "log", dir.path() / "a.bag"), InputError);
  RosbagExportOptions shifted;
  shifted.time_offset_ns = kNsPerSecond;
  const RosbagExportResult ok = ExportRosbag(dir.path() / "log", dir.path() / "b.bag", shifted);
  EXPECT_FALSE(ok.error.has_value());
  EXPECT_EQ(ok.streams.at(0).count, 2u);
}

}  // namespace
}  // namespace statebench::sensors
