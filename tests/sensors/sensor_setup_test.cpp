#include "sensors/sensor_setup.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "core/error.hpp"

namespace statebench::sensors {
namespace {

std::filesystem::path SourceDir() {
  const char* dir = std::getenv("STATEBENCH_SOURCE_DIR");
  return dir ? std::filesystem::path(dir) : std::filesystem::current_path();
}

SensorSetup Parse(const std::string& text) {
  return ParseSensorSetup(YamlNode::LoadString(text, "bad.yaml"));
}

// Returns the InputError message of parsing `text` (empty if it parsed).
std::string ErrorOf(const std::string& text) {
  try {
    Parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* const kImuEntry = R"(
  - type: imu
    id: imu
    rate_hz: 100
    latency_s: 0.0
    T_body_sensor: {translation: [0, 0, 0.5]}
    preset: tactical
)";

TEST(SensorSetup, PaperSetupsLoad) {
  const auto dir = SourceDir() / "scenarios" / "setups";
  const SensorSetup s1 = LoadSensorSetup(dir / "setup1_quadricycle.yaml");
  EXPECT_EQ(s1.name, "setup1_quadricycle");
  EXPECT_EQ(s1.OfType(SensorType::kGnss).size(), 2u);
  EXPECT_EQ(s1.OfType(SensorType::kLidar).size(), 1u);
  EXPECT_EQ(s1.OfType(SensorType::kImu).size(), 1u);
  EXPECT_EQ(s1.OfType(SensorType::kSteeringEncoder).size(), 1u);
  EXPECT_EQ(s1.OfType(SensorType::kSpeedEncoder).size(), 1u);
  EXPECT_EQ(s1.OfType(SensorType::kWheelEncoders).size(), 1u);
  ASSERT_EQ(s1.dual_antenna_headings.size(), 1u);
  EXPECT_EQ(s1.dual_antenna_headings[0].aux_antenna, "gnss_front");
  const SensorConfig* imu = s1.Find("imu");
  ASSERT_NE(imu, nullptr);
  EXPECT_DOUBLE_EQ(imu->spec.T_body_sensor.translation().z(), 0.50);
  EXPECT_DOUBLE_EQ(std::get<ImuOptions>(imu->options).gyro.noise_density, 1.7e-4);
  const auto& lidar = std::get<LidarOptions>(s1.Find("lidar_roof")->options);
  EXPECT_EQ(lidar.model, LidarModel::kHesaiXt32);

  const SensorSetup s2 = LoadSensorSetup(dir / "setup2_quadricycle.yaml");
  ASSERT_EQ(s2.OfType(SensorType::kGnss).size(), 1u);
  const auto& gnss = std::get<GnssOptions>(s2.Find("gnss_front")->options);
  EXPECT_EQ(gnss.mode, GnssMode::kSingle);
  EXPECT_NEAR(gnss.AccuracyOf(GnssMode::kSingle).HorizontalSigma(), 1.699, 1e-3);
  EXPECT_EQ(gnss.correlated_fraction, 0.01);
  EXPECT_TRUE(s2.dual_antenna_headings.empty());

  const SensorSetup s3 = LoadSensorSetup(dir / "setup3_shuttle.yaml");
  const auto lidars = s3.OfType(SensorType::kLidar);
  ASSERT_EQ(lidars.size(), 2u);
  EXPECT_EQ(std::get<LidarOptions>(lidars[1]->options).model, LidarModel::kVelodyneVlp16);
  EXPECT_LT(lidars[1]->spec.T_body_sensor.translation().x(), 0.0);
  EXPECT_DOUBLE_EQ(s3.Find("gnss_roof")->spec.T_body_sensor.translation().z(), 2.80);
}

TEST(SensorSetup, UnknownSensorTypeNamesFileLineAndField) {
  const std::string msg = ErrorOf(R"(name: x
sensors:
  - type: radar
    id: r
)");
  EXPECT_NE(msg.find("bad.yaml:3:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("sensors[0].type"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unknown sensor type 'radar'"), std::string::npos) << msg;
}

TEST(SensorSetup, MissingFieldNamesFileLineAndField) {
  const std::string msg = ErrorOf(std::string("name: x\nsensors:") + kImuEntry + R"(
  - type: gnss
    id: gnss
    rate_hz: 10
    T_body_sensor: {translation: [0, 0, 1.5]}
    mode: single
)");
  EXPECT_NE(msg.find("bad.yaml:10:5:"), std::string::npos) << msg;  // the entry's line
  EXPECT_NE(msg.find("sensors[1].latency_s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing field"), std::string::npos) << msg;
}

TEST(SensorSetup, NonFiniteNumberIsRefusedNamingFileLineAndField) {
  const std::string msg = ErrorOf(std::string("name: x\nsensors:") + kImuEntry + R"(
  - type: gnss
    id: gnss
    rate_hz: 10
    latency_s: .nan
    T_body_sensor: {translation: [0, 0, 1.5]}
    mode: single
)");
  EXPECT_NE(msg.find("bad.yaml:13:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("sensors[1].latency_s"), std::string::npos) << msg;
}

TEST(SensorSetup, WrongTypeNamesFileLineAndField) {
  const std::string msg = ErrorOf(std::string("name: x\nsensors:") + kImuEntry + R"(
  - type: gnss
    id: gnss
    rate_hz: fast
    latency_s: 0.1
    T_body_sensor: {translation: [0, 0, 1.5]}
    mode: single
)");
  EXPECT_NE(msg.find("bad.yaml:12:14"), std::string::npos) << msg;
  EXPECT_NE(msg.find("sensors[1].rate_hz"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected a number, got 'fast'"), std::string::npos) << msg;
}

TEST(SensorSetup, OtherMistakesAreCaughtWithTheirField) {
  const std::string head = std::string("name: x\nsensors:") + kImuEntry;
  // A typo in a type-specific key.
  std::string msg = ErrorOf(head + R"(
  - type: gnss
    id: gnss
    rate_hz: 10
    latency_s: 0.1
    T_body_sensor: {translation: [0, 0, 1.5]}
    mode: single
    cep: 2.0
)");
  EXPECT_NE(msg.find("bad.yaml:16:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'sensors[1].cep': unknown field"), std::string::npos) << msg;
  // A rate that does not divide the 1 kHz truth rate.
  msg = ErrorOf(head + R"(
  - type: gnss
    id: gnss
    rate_hz: 3
    latency_s: 0.1
    T_body_sensor: {translation: [0, 0, 1.5]}
    mode: single
)");
  EXPECT_NE(msg.find("bad.yaml:12:14: field 'sensors[1].rate_hz'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("does not divide"), std::string::npos) << msg;
  // An unknown mode, a duplicate id, an unknown lidar model, a bad heading pair.
  msg = ErrorOf(head +
                "  - {type: gnss, id: g, rate_hz: 10, latency_s: 0, T_body_sensor: {}, "
                "mode: dgps}\n");
  EXPECT_NE(msg.find("sensors[1].mode': unknown mode 'dgps'"), std::string::npos) << msg;
  msg = ErrorOf(head + kImuEntry);
  EXPECT_NE(msg.find("sensors[1].id': duplicate sensor id 'imu'"), std::string::npos) << msg;
  msg = ErrorOf(head +
                "  - {type: lidar, id: l, rate_hz: 10, latency_s: 0, T_body_sensor: {}, "
                "model: ouster}\n");
  EXPECT_NE(msg.find("sensors[1].model': unknown lidar model 'ouster'"), std::string::npos) << msg;
  msg = ErrorOf(head + "dual_antenna_headings:\n  - {id: h, main: imu, aux: nothing}\n");
  EXPECT_NE(msg.find("dual_antenna_headings[0].main': no gnss sensor with id 'imu'"),
            std::string::npos)
      << msg;
  // Without a preset the IMU noise terms are required.
  msg = ErrorOf(R"(name: x
sensors:
  - type: imu
    id: imu
    rate_hz: 200
    latency_s: 0.0
    T_body_sensor: {}
    gyro: {noise_density: 1e-4, random_walk: 1e-5}
    accel: {noise_density: 1e-3}
)");
  EXPECT_NE(msg.find("bad.yaml:9:12: field 'sensors[0].accel.random_walk': missing field"),
            std::string::npos)
      << msg;
}

TEST(SensorSetup, ExplicitValuesOverrideThePreset) {
  const SensorSetup s = Parse(R"(name: x
sensors:
  - type: imu
    id: imu
    rate_hz: 200
    latency_s: 0.0
    T_body_sensor: {translation: [0.1, 0.2, 0.3], rpy_deg: [0, 0, 90]}
    preset: consumer
    gyro: {noise_density: 1e-3, gauss_markov: {sigma: 1e-4, tau_s: 300}}
  - type: gnss
    id: g
    rate_hz: 5
    latency_s: 0.2
    T_body_sensor: {translation: [0, 0, 1.5]}
    mode: rtk_float
    cep_m: 0.5
    outages: [{start_s: 60}]
    multipath: {events_per_hour: 12}
)");
  const auto& imu = std::get<ImuOptions>(s.Find("imu")->options);
  EXPECT_EQ(imu.gyro.noise_density, 1e-3);
  EXPECT_EQ(imu.gyro.random_walk, ImuPreset(ImuGrade::kConsumer).gyro.random_walk);
  EXPECT_EQ(imu.gyro.gauss_markov_tau_s, 300.0);
  EXPECT_EQ(imu.accel.noise_density, ImuPreset(ImuGrade::kConsumer).accel.noise_density);
  const auto& g = std::get<GnssOptions>(s.Find("g")->options);
  EXPECT_EQ(g.AccuracyOf(GnssMode::kRtkFloat).cep_m, 0.5);
  EXPECT_NEAR(g.AccuracyOf(GnssMode::kRtkFloat).vertical_sigma_m, 1.5 * 0.5 / 1.17741, 1e-4);
  ASSERT_EQ(g.outages.size(), 1u);
  EXPECT_TRUE(std::isinf(g.outages[0].end_s));
  EXPECT_EQ(g.multipath.events_per_hour, 12.0);
  EXPECT_EQ(s.Find("g")->spec.PeriodNs(), 200 * kNsPerMillisecond);
}

}  // namespace
}  // namespace statebench::sensors
