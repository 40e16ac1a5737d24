#include "estimator/estimator_config.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <numbers>

#include "core/error.hpp"

namespace statebench::est {
namespace {

std::filesystem::path SourceDir() {
  const char* dir = std::getenv("STATEBENCH_SOURCE_DIR");
  return dir != nullptr ? std::filesystem::path(dir) : std::filesystem::current_path();
}

EstimatorSensorSetup Parse(const std::string& yaml) {
  return ParseEstimatorSensorSetup(YamlNode::LoadString(yaml, "setup.yaml"));
}

// The InputError message of parsing yaml (empty if it parses).
template <typename ParseFn>
std::string ErrorOf(ParseFn parse, const std::string& yaml) {
  try {
    parse(YamlNode::LoadString(yaml, "setup.yaml"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const std::string kImu =
    "  - {type: imu, id: imu, rate_hz: 100, latency_s: 0.002, T_body_sensor: {translation: [0, 0, "
    "0.5]}, preset: industrial}\n";

TEST(EstimatorSensorSetup, ReadsThePaperSetupsInTheImuFrame) {
  const auto setup1 =
      LoadEstimatorSensorSetup(SourceDir() / "scenarios/setups/setup1_quadricycle.yaml");
  EXPECT_EQ(setup1.name, "setup1_quadricycle");
  EXPECT_EQ(setup1.imu_id, "imu");
  ASSERT_EQ(setup1.antennas.size(), 2u);
  const GnssAntenna* front = setup1.FindAntenna("gnss_front");
  const GnssAntenna* rear = setup1.FindAntenna("gnss_rear");
  ASSERT_TRUE(front != nullptr && rear != nullptr);
  // T_imu_sensor = T_body_imu^-1 T_body_sensor, IMU 0.5 m above the body origin.
  EXPECT_TRUE(front->p_imu_antenna.isApprox(Vec3(0.45, 0.0, 1.0), 1e-12));
  EXPECT_TRUE(rear->p_imu_antenna.isApprox(Vec3(-0.80, 0.0, 1.0), 1e-12));
  ASSERT_EQ(setup1.dual_antennas.size(), 1u);
  const DualAntennaPair* pair = setup1.FindHeading("gnss_heading");
  ASSERT_NE(pair, nullptr);
  EXPECT_EQ(pair->main, "gnss_rear");
  EXPECT_EQ(pair->aux, "gnss_front");
  EXPECT_DOUBLE_EQ(setup1.MaxMeasurementLatency(), 0.10);
  EXPECT_NEAR(FactorGraphOptions{}.ReorderLatency(setup1), 0.10 + kReorderMarginS, 1e-12);
  ASSERT_NE(setup1.Find("lidar_roof"), nullptr);
  EXPECT_EQ(setup1.Find("lidar_roof")->kind, SensorKind::kLidar);
  EXPECT_EQ(setup1.Find("wheels")->kind, SensorKind::kWheelEncoders);
  EXPECT_FALSE(setup1.imu_noise.has_value());

  const auto setup2 =
      LoadEstimatorSensorSetup(SourceDir() / "scenarios/setups/setup2_quadricycle.yaml");
  EXPECT_EQ(setup2.antennas.size(), 1u);
  EXPECT_TRUE(setup2.dual_antennas.empty());
  // Setup 2's receiver describes its slow error (sqrt(0.01) of its sigmas); setup 1's do not.
  EXPECT_DOUBLE_EQ(setup2.antennas[0].correlated_error_sigma_m, 0.17);
  EXPECT_DOUBLE_EQ(setup2.antennas[0].correlated_error_vertical_sigma_m, 0.255);
  EXPECT_DOUBLE_EQ(setup2.antennas[0].correlated_error_tau_s, 100.0);
  EXPECT_FALSE(front->DescribesCorrelatedError());

  const auto setup3 =
      LoadEstimatorSensorSetup(SourceDir() / "scenarios/setups/setup3_shuttle.yaml");
  const EstimatorSensor* rear_lidar = setup3.Find("lidar_rear");
  ASSERT_NE(rear_lidar, nullptr);
  EXPECT_TRUE(rear_lidar->T_imu_sensor.translation().isApprox(Vec3(-1.95, 0.0, 1.15), 1e-12));
  EXPECT_TRUE(
      (rear_lidar->T_imu_sensor.rotation() * Vec3::UnitX()).isApprox(-Vec3::UnitX(), 1e-12));
}

TEST(EstimatorSensorSetup, ARotatedImuSeesTheLeverArmsInItsOwnFrame) {
  const auto setup = Parse(
      "name: rotated\nsensors:\n"
      "  - {type: imu, id: imu, T_body_sensor: {translation: [0.2, 0, 0.5], rpy_deg: [0, 0, 90]}}\n"
      "  - {type: gnss, id: gps, T_body_sensor: {translation: [1.2, 0, 1.5]}}\n");
  // p_imu = R_body_imu^T (p_body - t_body_imu) = Rz(-90 deg) (1, 0, 1) = (0, -1, 1).
  EXPECT_TRUE(setup.FindAntenna("gps")->p_imu_antenna.isApprox(Vec3(0.0, -1.0, 1.0), 1e-12));
}

TEST(EstimatorSensorSetup, PairsTwoAntennasWithoutAHeadingEntry) {
  const auto setup =
      Parse("name: two\nsensors:\n" + kImu +
            "  - {type: gnss, id: a, T_body_sensor: {translation: [1, 0, 1.5]}, latency_s: 0.2}\n"
            "  - {type: gnss, id: b, T_body_sensor: {translation: [-1, 0, 1.5]}}\n");
  ASSERT_EQ(setup.dual_antennas.size(), 1u);
  EXPECT_TRUE(setup.dual_antennas[0].heading_id.empty());
  EXPECT_EQ(setup.dual_antennas[0].main, "a");
  EXPECT_EQ(setup.dual_antennas[0].aux, "b");
  EXPECT_TRUE((setup.dual_antennas[0].p_imu_aux - setup.dual_antennas[0].p_imu_main)
                  .isApprox(Vec3(-2, 0, 0), 1e-12));
  EXPECT_DOUBLE_EQ(setup.MaxMeasurementLatency(), 0.2);
}

TEST(EstimatorSensorSetup, ReadsEstimatorOverrides) {
  const auto setup = Parse(
      "name: o\nsensors:\n"
      "  - {type: imu, id: imu, T_body_sensor: {}, estimator: {gyro_noise_density: 3e-4, "
      "accel_random_walk: 1e-3}}\n"
      "  - {type: gnss, id: g, T_body_sensor: {}, estimator: {covariance_scale: 4, min_sigma_m: "
      "0.02}}\n");
  ASSERT_TRUE(setup.imu_noise.has_value());
  EXPECT_DOUBLE_EQ(setup.imu_noise->gyro_noise_density, 3e-4);
  EXPECT_DOUBLE_EQ(setup.imu_noise->accel_random_walk, 1e-3);
  EXPECT_DOUBLE_EQ(setup.imu_noise->accel_noise_density, ImuNoise{}.accel_noise_density);
  EXPECT_DOUBLE_EQ(setup.FindAntenna("g")->covariance_scale, 4.0);
  EXPECT_DOUBLE_EQ(setup.FindAntenna("g")->min_sigma_m, 0.02);
  EXPECT_FALSE(setup.FindAntenna("g")->DescribesCorrelatedError());
}

TEST(EstimatorSensorSetup, AReceiversSlowErrorIsDescribedByAllThreeFiguresOrNone) {
  const auto setup = Parse(
      "name: o\nsensors:\n  - {type: imu, id: imu, T_body_sensor: {}}\n"
      "  - {type: gnss, id: g, T_body_sensor: {}, estimator: {correlated_error_sigma_m: 0.2, "
      "correlated_error_vertical_sigma_m: 0.3, correlated_error_tau_s: 60}}\n");
  const GnssAntenna& g = *setup.FindAntenna("g");
  EXPECT_TRUE(g.DescribesCorrelatedError());
  EXPECT_DOUBLE_EQ(g.correlated_error_sigma_m, 0.2);
  EXPECT_DOUBLE_EQ(g.correlated_error_vertical_sigma_m, 0.3);
  EXPECT_DOUBLE_EQ(g.correlated_error_tau_s, 60.0);
  const auto parse = [](const YamlNode& n) { return ParseEstimatorSensorSetup(n); };
  const std::string partial = ErrorOf(
      parse, "name: x\nsensors:\n" + kImu +
                 "  - {type: gnss, id: g, T_body_sensor: {}, estimator: {correlated_error_sigma_m: "
                 "0.2}}\n");
  EXPECT_NE(partial.find("setup.yaml:4:"), std::string::npos) << partial;
  EXPECT_NE(partial.find("give all three above 0, or none"), std::string::npos) << partial;
  EXPECT_NE(ErrorOf(parse, "name: x\nsensors:\n" + kImu +
                               "  - {type: gnss, id: g, T_body_sensor: {}, estimator: "
                               "{correlated_error_tau_s: -1}}\n")
                .find("correlated_error_tau_s"),
            std::string::npos);
}

TEST(EstimatorSensorSetup, ErrorsNameTheFileLineAndField) {
  const auto parse = [](const YamlNode& n) { return ParseEstimatorSensorSetup(n); };
  const std::string radar = ErrorOf(
      parse, "name: x\nsensors:\n" + kImu + "  - type: radar\n    id: r\n    T_body_sensor: {}\n");
  EXPECT_NE(radar.find("setup.yaml:4:"), std::string::npos) << radar;
  EXPECT_NE(radar.find("unknown sensor type 'radar'"), std::string::npos) << radar;
  EXPECT_NE(radar.find("sensors[1].type"), std::string::npos) << radar;

  EXPECT_NE(ErrorOf(parse, "name: x\nsensors:\n" + kImu + kImu).find("duplicate sensor id 'imu'"),
            std::string::npos);
  EXPECT_NE(ErrorOf(parse, "name: x\nsensors:\n  - {type: gnss, id: g, T_body_sensor: {}}\n")
                .find("no imu"),
            std::string::npos);
  EXPECT_NE(ErrorOf(parse,
                    "name: x\nsensors:\n" + kImu + "  - {type: imu, id: imu2, T_body_sensor: {}}\n")
                .find("a second imu"),
            std::string::npos);
  const std::string typo =
      ErrorOf(parse,
              "name: x\nsensors:\n  - {type: imu, id: imu, T_body_sensor: {}, estimator: "
              "{gyro_noise: 1e-4}}\n");
  EXPECT_NE(typo.find("setup.yaml:3:"), std::string::npos) << typo;
  EXPECT_NE(typo.find("gyro_noise"), std::string::npos) << typo;
  EXPECT_NE(ErrorOf(parse, "name: x\nsensors:\n" + kImu +
                               "  - {type: gnss, id: g, T_body_sensor: {translation: [1]}}\n")
                .find("T_body_sensor.translation"),
            std::string::npos);
  EXPECT_NE(ErrorOf(parse, "name: x\nsensors:\n" + kImu +
                               "  - {type: gnss, id: g, T_body_sensor: {}}\n"
                               "dual_antenna_headings:\n  - {id: h, main: g, aux: imu}\n")
                .find("no gnss sensor with id 'imu'"),
            std::string::npos);
}

TEST(FactorGraphOptions, TheDefaultFileHoldsTheDefaults) {
  const FactorGraphOptions file =
      LoadFactorGraphOptions(SourceDir() / "scenarios/estimators/factor_graph.yaml");
  const FactorGraphOptions d;
  EXPECT_TRUE(d.IsValid());
  EXPECT_DOUBLE_EQ(file.window_s, d.window_s);
  EXPECT_EQ(file.imu_samples_per_state, d.imu_samples_per_state);
  EXPECT_DOUBLE_EQ(file.solve_interval_s, d.solve_interval_s);
  EXPECT_FALSE(file.reorder_latency_s.has_value());
  EXPECT_EQ(file.max_iterations, d.max_iterations);
  EXPECT_FALSE(file.origin.has_value());
  EXPECT_DOUBLE_EQ(file.imu_noise.gyro_noise_density, d.imu_noise.gyro_noise_density);
  EXPECT_DOUBLE_EQ(file.imu_noise.accel_random_walk, d.imu_noise.accel_random_walk);
  EXPECT_DOUBLE_EQ(file.imu_noise.integration_density, d.imu_noise.integration_density);
  EXPECT_EQ(file.imu_triad.estimate_gyro, d.imu_triad.estimate_gyro);
  EXPECT_EQ(file.imu_triad.estimate_accel, d.imu_triad.estimate_accel);
  EXPECT_DOUBLE_EQ(file.imu_triad.gyro_scale_sigma, d.imu_triad.gyro_scale_sigma);
  EXPECT_DOUBLE_EQ(file.imu_triad.gyro_misalignment_sigma_rad,
                   d.imu_triad.gyro_misalignment_sigma_rad);
  EXPECT_DOUBLE_EQ(file.imu_triad.accel_scale_sigma, d.imu_triad.accel_scale_sigma);
  EXPECT_DOUBLE_EQ(file.imu_triad.accel_misalignment_sigma_rad,
                   d.imu_triad.accel_misalignment_sigma_rad);
  EXPECT_DOUBLE_EQ(file.imu_triad.max_sigmas, d.imu_triad.max_sigmas);
  EXPECT_EQ(file.initialization.mode, d.initialization.mode);
  EXPECT_DOUBLE_EQ(file.initialization.course_min_distance_m,
                   d.initialization.course_min_distance_m);
  EXPECT_DOUBLE_EQ(file.initialization.accel_bias_sigma_mps2,
                   d.initialization.accel_bias_sigma_mps2);
  EXPECT_DOUBLE_EQ(file.gnss.max_sigma, d.gnss.max_sigma);
  EXPECT_DOUBLE_EQ(file.gnss.gate_chi2, d.gnss.gate_chi2);
  EXPECT_DOUBLE_EQ(file.heading.max_sigma, d.heading.max_sigma);
  EXPECT_DOUBLE_EQ(file.heading.gate_chi2, d.heading.gate_chi2);
  EXPECT_EQ(file.gnss.kernel.type, d.gnss.kernel.type);
  EXPECT_DOUBLE_EQ(file.gnss.kernel.scale, d.gnss.kernel.scale);
}

TEST(FactorGraphOptions, ParsesValuesAndRejectsTyposAndBadValues) {
  const auto parse = [](const YamlNode& n) { return ParseFactorGraphOptions(n); };
  const FactorGraphOptions o = ParseFactorGraphOptions(YamlNode::LoadString(
      "window_s: 2\nimu_samples_per_state: 1\nreorder_latency_s: 0.5\n"
      "origin: {latitude_deg: 45, longitude_deg: 7, altitude_m: 300}\n"
      "initialization: {mode: static}\ngnss: {robust_kernel: {type: cauchy, scale: 2}}\n",
      "options.yaml"));
  EXPECT_DOUBLE_EQ(o.window_s, 2.0);
  EXPECT_EQ(o.imu_samples_per_state, 1);
  EXPECT_DOUBLE_EQ(*o.reorder_latency_s, 0.5);
  ASSERT_TRUE(o.origin.has_value());
  EXPECT_DOUBLE_EQ(o.origin->altitude_m, 300.0);
  EXPECT_EQ(o.initialization.mode, InitializationMode::kStatic);
  EXPECT_EQ(o.gnss.kernel.type, RobustKernelType::kCauchy);
  EXPECT_DOUBLE_EQ(o.gnss.kernel.scale, 2.0);

  const std::string typo = ErrorOf(parse, "window_s: 1\nwindow_length: 2\n");
  EXPECT_NE(typo.find("setup.yaml:2:"), std::string::npos) << typo;
  EXPECT_NE(typo.find("window_length"), std::string::npos) << typo;
  EXPECT_NE(ErrorOf(parse, "window_s: -1\n").find("window_s"), std::string::npos);
  EXPECT_NE(ErrorOf(parse, "imu_samples_per_state: 0\n").find("at least 1"), std::string::npos);
  EXPECT_NE(ErrorOf(parse, "gnss: {robust_kernel: {type: tukey}}\n").find("tukey"),
            std::string::npos);
  EXPECT_NE(ErrorOf(parse, "initialization: {mode: flying}\n").find("flying"), std::string::npos);
  EXPECT_NE(ErrorOf(parse, "origin: {latitude_deg: 91, longitude_deg: 0}\n").find("latitude_deg"),
            std::string::npos);
}

}  // namespace
}  // namespace statebench::est
