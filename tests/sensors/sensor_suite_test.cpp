#include "sensors/sensor_suite.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>

#include "truth_fixtures.hpp"

namespace statebench::sensors {
namespace {

const GeodeticPoint kOrigin{48.7846, 2.1360, 130.0};

SensorSetup Setup1() {
  const char* dir = std::getenv("STATEBENCH_SOURCE_DIR");
  const std::filesystem::path root = dir ? dir : std::filesystem::current_path();
  return LoadSensorSetup(root / "scenarios" / "setups" / "setup1_quadricycle.yaml");
}

// Runs setup 1 over `seconds` of a circle drive and returns the stream. Checks on the way that
// Push releases only what arrived by t + the smallest latency (2 ms).
std::vector<Measurement> RunSetup1(std::uint64_t seed, double seconds) {
  SensorSuite suite(Setup1(), LocalEnuFrame(kOrigin), seed);
  const testing::Circle circle;
  std::vector<Measurement> stream;
  for (TimeNs t = 0; t <= FromSeconds(seconds); t += kNsPerMillisecond) {
    const std::size_t before = stream.size();
    suite.Push(circle.At(t), &stream);
    for (std::size_t i = before; i < stream.size(); ++i) {
      EXPECT_LE(HeaderOf(stream[i]).arrival_ns, t + 2 * kNsPerMillisecond);
    }
  }
  suite.Finish(&stream);
  return stream;
}

// Every field of a measurement as raw bytes, for bitwise comparison.
template <typename T>
void AppendBytes(const T& value, std::string* out) {
  const auto* p = reinterpret_cast<const char*>(&value);
  out->append(p, p + sizeof(T));
}

std::string Bytes(const Measurement& m) {
  std::string out;
  const MeasurementHeader& h = HeaderOf(m);
  out += h.sensor_id;
  AppendBytes(h.stamp_ns, &out);
  AppendBytes(h.arrival_ns, &out);
  std::visit(
      [&out](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, ImuSample>) {
          AppendBytes(x.gyro, &out);
          AppendBytes(x.accel, &out);
        } else if constexpr (std::is_same_v<T, GnssFix>) {
          AppendBytes(x.latitude_deg, &out);
          AppendBytes(x.longitude_deg, &out);
          AppendBytes(x.altitude_m, &out);
          AppendBytes(x.covariance_enu, &out);
          AppendBytes(x.status, &out);
        } else if constexpr (std::is_same_v<T, DualAntennaHeading>) {
          AppendBytes(x.yaw_rad, &out);
          AppendBytes(x.pitch_rad, &out);
          AppendBytes(x.yaw_sigma_rad, &out);
          AppendBytes(x.pitch_sigma_rad, &out);
        } else if constexpr (std::is_same_v<T, WheelSpeeds>) {
          AppendBytes(x.omega_radps, &out);
        } else if constexpr (std::is_same_v<T, VehicleSpeed>) {
          AppendBytes(x.speed_mps, &out);
        } else if constexpr (std::is_same_v<T, SteeringAngle>) {
          AppendBytes(x.angle_rad, &out);
        }
      },
      m);
  return out;
}

TEST(SensorSuite, EmitsEverySensorOfSetup1InArrivalOrder) {
  const std::vector<Measurement> stream = RunSetup1(7, 5.0);
  std::map<std::string, int> count;
  for (std::size_t i = 0; i < stream.size(); ++i) {
    ++count[HeaderOf(stream[i]).sensor_id];
    if (i > 0) {
      EXPECT_FALSE(ArrivesBefore(stream[i], stream[i - 1])) << i;
    }
  }
  // 5 s from t = 0 inclusive. Encoders start counting at their first sample time.
  EXPECT_EQ(count["imu"], 501);
  EXPECT_EQ(count["gnss_front"], 51);
  EXPECT_EQ(count["gnss_rear"], 51);
  EXPECT_EQ(count["gnss_heading"], 51);
  EXPECT_EQ(count["steering"], 251);
  EXPECT_EQ(count["speed"], 250);
  EXPECT_EQ(count["wheels"], 250);
  EXPECT_EQ(count.count("lidar_roof"), 0u);  // simulated by the lidar module
  // Latency: the GNSS fix taken at 1 s arrives at 1.1 s, after the IMU sample of 1.05 s.
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < stream.size(); ++i) {
    const MeasurementHeader& h = HeaderOf(stream[i]);
    index[h.sensor_id + "@" + std::to_string(h.stamp_ns)] = i;
  }
  EXPECT_LT(index.at("imu@1050000000"), index.at("gnss_front@1000000000"));
  EXPECT_LT(index.at("gnss_front@1000000000"), index.at("imu@1100000000"));
  for (const Measurement& m : stream) {
    const MeasurementHeader& h = HeaderOf(m);
    if (h.sensor_id == "gnss_front") {
      EXPECT_EQ(h.arrival_ns - h.stamp_ns, 100 * kNsPerMillisecond);
    } else if (h.sensor_id == "imu") {
      EXPECT_EQ(h.arrival_ns - h.stamp_ns, 2 * kNsPerMillisecond);
    }
  }
}

TEST(SensorSuite, SameSeedSameBitsDifferentSeedDifferentBits) {
  const std::vector<Measurement> a = RunSetup1(7, 2.0);
  const std::vector<Measurement> b = RunSetup1(7, 2.0);
  const std::vector<Measurement> c = RunSetup1(8, 2.0);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());  // the schedule does not depend on the seed
  std::map<std::string, int> differing;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(Bytes(a[i]), Bytes(b[i])) << i;
    EXPECT_EQ(HeaderOf(a[i]).sensor_id, HeaderOf(c[i]).sensor_id);
    if (Bytes(a[i]) != Bytes(c[i])) ++differing[HeaderOf(a[i]).sensor_id];
  }
  // Every noisy sensor differs with another seed (sample by sample for the white-noise ones).
  EXPECT_EQ(differing["imu"], 201);
  EXPECT_EQ(differing["gnss_front"], 21);
  EXPECT_EQ(differing["gnss_heading"], 21);
  EXPECT_GT(differing["steering"], 0);  // 0.5 mrad noise, mostly hidden by 1.75 mrad steps
  EXPECT_GT(differing["wheels"], 0);    // random tick phase
}

TEST(SensorSuite, SimulatedSourceYieldsTheSameStreamAsPush) {
  const std::vector<Measurement> pushed = RunSetup1(3, 1.0);
  const testing::Circle circle;
  TimeNs t = 0;
  SimulatedMeasurementSource source(
      std::make_unique<SensorSuite>(Setup1(), LocalEnuFrame(kOrigin), 3),
      [&]() -> std::optional<TruthSample> {
        if (t > kNsPerSecond) return std::nullopt;
        const TruthSample s = circle.At(t);
        t += kNsPerMillisecond;
        return s;
      });
  std::vector<Measurement> pulled;
  while (auto m = source.Next()) pulled.push_back(std::move(*m));
  ASSERT_EQ(pulled.size(), pushed.size());
  for (std::size_t i = 0; i < pulled.size(); ++i) EXPECT_EQ(Bytes(pulled[i]), Bytes(pushed[i]));
}

}  // namespace
}  // namespace statebench::sensors
