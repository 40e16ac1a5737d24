// A scenario's `mismatch:`: the simulated unit differs from the setup file the estimators read,
// drawn from the seed (same seed, same unit), within the configured spreads; bad blocks name their
// line and field.
#include "simulator/scenario_mismatch.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "simulator/scenario_sensors.hpp"
#include "sumo_test_support.hpp"

namespace statebench::sim {
namespace {

using testing::GridScenarioParts;
using testing::InputErrorOf;
using testing::TempDir;
using testing::WriteFile;

constexpr const char* kSensors = "sensors: setup2_quadricycle.yaml\n";
constexpr const char* kMismatch =
    "mismatch:\n"
    "  imu_spread: 0.3\n"
    "  gnss_covariance_scale: [0.5, 2.0]\n"
    "  gnss_slow_error_scale: [0.5, 2.0]\n"
    "  mount_translation_sigma_m: 0.01\n"
    "  mount_rotation_sigma_deg: 0.2\n"
    "  clock_offset_sigma_s: 0.003\n"
    "  vehicle_mass_spread: 0.1\n"
    "  vehicle_cornering_stiffness_spread: 0.2\n";

Scenario GridWith(const TempDir& dir, const std::string& rest, std::uint64_t seed = 7) {
  GridScenarioParts parts;
  parts.rest += rest;
  std::string text = parts.Text();
  const std::size_t at = text.find("seed: ");
  text.replace(at, text.find('\n', at) - at, "seed: " + std::to_string(seed));
  return LoadScenario(WriteFile(dir.path() / "town" / "grid.yaml", text));
}

TEST(ScenarioMismatch, TheSimulatedUnitDiffersFromTheSetupWithinItsSpreads) {
  TempDir dir;
  const ScenarioSensors nominal = LoadScenarioSensors(GridWith(dir, kSensors));
  const ScenarioSensors unit = LoadScenarioSensors(GridWith(dir, std::string(kSensors) + kMismatch));
  EXPECT_TRUE(nominal.mismatch.empty());
  ASSERT_EQ(unit.mismatch.size(), unit.setup.sensors.size());
  // The estimators read the setup as written.
  EXPECT_EQ(unit.setup_yaml, nominal.setup_yaml);
  int clock_faults = 0;
  for (const MeasurementFault& f : unit.faults.injected) {
    clock_faults += f.kind == MeasurementFaultKind::kClockJump;
  }
  EXPECT_EQ(clock_faults, static_cast<int>(unit.setup.sensors.size()) - 1);  // all but the IMU
  for (std::size_t i = 0; i < unit.setup.sensors.size(); ++i) {
    const auto& a = nominal.setup.sensors[i];
    const auto& b = unit.setup.sensors[i];
    const SensorMismatch& m = unit.mismatch[i];
    SCOPED_TRACE(m.id);
    const Vec3 dt = b.spec.T_body_sensor.translation() - a.spec.T_body_sensor.translation();
    EXPECT_LT(dt.norm(), 0.06);  // 1 cm per axis: 5 sigma of the norm
    EXPECT_GT(dt.norm(), 0.0);
    EXPECT_NEAR((dt - m.mount_translation_m).norm(), 0.0, 1e-12);
    EXPECT_LT(m.mount_rotation_deg.norm(), 1.0);
    EXPECT_LT(std::abs(m.clock_offset_s), 0.015);
    if (b.type() == sensors::SensorType::kGnss) {
      const double scale = std::get<sensors::GnssOptions>(b.options).covariance_scale /
                           std::get<sensors::GnssOptions>(a.options).covariance_scale;
      EXPECT_DOUBLE_EQ(scale, m.reported_covariance_scale);
      EXPECT_GE(scale, 0.5);
      EXPECT_LE(scale, 2.0);
      // The unit's slow error: the setup's variance fraction (0.01) x the drawn factor.
      const double fraction = std::get<sensors::GnssOptions>(b.options).correlated_fraction;
      EXPECT_DOUBLE_EQ(fraction, std::get<sensors::GnssOptions>(a.options).correlated_fraction *
                                     m.slow_error_variance_factor);
      EXPECT_GE(m.slow_error_variance_factor, 0.5);
      EXPECT_LE(m.slow_error_variance_factor, 2.0);
      EXPECT_NE(m.slow_error_variance_factor, 1.0);
    }
    if (b.type() == sensors::SensorType::kImu) {
      const auto& ia = std::get<sensors::ImuOptions>(a.options);
      const auto& ib = std::get<sensors::ImuOptions>(b.options);
      const double f = ib.gyro.noise_density / ia.gyro.noise_density;
      EXPECT_DOUBLE_EQ(f, m.gyro_noise_factor);
      EXPECT_GE(f, 0.7);
      EXPECT_LE(f, 1.3);
      EXPECT_NE(f, 1.0);
      EXPECT_DOUBLE_EQ(ib.accel.random_walk / ia.accel.random_walk, m.accel_walk_factor);
    }
  }
  // Same seed, same unit; another seed, another unit.
  const ScenarioSensors again = LoadScenarioSensors(GridWith(dir, std::string(kSensors) + kMismatch));
  EXPECT_EQ(again.mismatch[0].mount_translation_m, unit.mismatch[0].mount_translation_m);
  const ScenarioSensors other =
      LoadScenarioSensors(GridWith(dir, std::string(kSensors) + kMismatch, 8));
  EXPECT_NE(other.mismatch[0].mount_translation_m, unit.mismatch[0].mount_translation_m);
}

// The slow error's draws come from a stream of their own: with or without them, every other
// quantity of the unit is drawn the same (the figures measured before the option stay valid).
TEST(ScenarioMismatch, TheSlowErrorScaleLeavesTheOtherDrawsAsTheyWere) {
  TempDir dir;
  std::string without = kMismatch;
  const std::string line = "  gnss_slow_error_scale: [0.5, 2.0]\n";
  without.erase(without.find(line), line.size());
  const ScenarioSensors a = LoadScenarioSensors(GridWith(dir, std::string(kSensors) + without));
  const ScenarioSensors b = LoadScenarioSensors(GridWith(dir, std::string(kSensors) + kMismatch));
  ASSERT_EQ(a.mismatch.size(), b.mismatch.size());
  bool some_gnss = false;
  for (std::size_t i = 0; i < a.mismatch.size(); ++i) {
    SCOPED_TRACE(a.mismatch[i].id);
    EXPECT_EQ(a.mismatch[i].mount_translation_m, b.mismatch[i].mount_translation_m);
    EXPECT_EQ(a.mismatch[i].mount_rotation_deg, b.mismatch[i].mount_rotation_deg);
    EXPECT_EQ(a.mismatch[i].clock_offset_s, b.mismatch[i].clock_offset_s);
    EXPECT_EQ(a.mismatch[i].reported_covariance_scale, b.mismatch[i].reported_covariance_scale);
    EXPECT_EQ(a.mismatch[i].gyro_noise_factor, b.mismatch[i].gyro_noise_factor);
    EXPECT_EQ(a.mismatch[i].slow_error_variance_factor, 1.0);
    if (b.setup.sensors[i].type() == sensors::SensorType::kGnss) {
      some_gnss = true;
      EXPECT_NE(b.mismatch[i].slow_error_variance_factor, 1.0);
    }
  }
  EXPECT_TRUE(some_gnss);
}

TEST(ScenarioMismatch, TheEstimatorsVehicleFileHasDrawnParameters) {
  TempDir dir;
  const Scenario scenario = GridWith(dir, std::string(kSensors) + kMismatch);
  const std::filesystem::path out = dir.path() / "vehicle_estimators.yaml";
  const VehicleMismatch v =
      WriteEstimatorVehicleFile(*scenario.mismatch, scenario.seed, scenario.vehicle_file, out);
  const YamlNode a = YamlNode::LoadFile(scenario.vehicle_file);
  const YamlNode b = YamlNode::LoadFile(out);
  EXPECT_DOUBLE_EQ(b.Get<double>("mass_kg"), a.Get<double>("mass_kg") * v.mass_factor);
  EXPECT_DOUBLE_EQ(b.Get<double>("yaw_inertia_kgm2"),
                   a.Get<double>("yaw_inertia_kgm2") * v.mass_factor);
  EXPECT_DOUBLE_EQ(b.Get<double>("cornering_stiffness_rear_npr"),
                   a.Get<double>("cornering_stiffness_rear_npr") * v.cornering_stiffness_rear_factor);
  EXPECT_NEAR(v.mass_factor, 1.0, 0.1);
  EXPECT_NE(v.mass_factor, 1.0);
  EXPECT_NEAR(v.cornering_stiffness_front_factor, 1.0, 0.2);
  EXPECT_EQ(b.Get<double>("wheel_radius_m"), a.Get<double>("wheel_radius_m"));
}

TEST(ScenarioMismatch, BadBlocksNameTheirField) {
  TempDir dir;
  const auto error = [&](const std::string& block) {
    return InputErrorOf([&] { GridWith(dir, std::string(kSensors) + "mismatch:\n" + block); });
  };
  EXPECT_NE(error("  imu_sprad: 0.3\n").find("imu_sprad"), std::string::npos);
  EXPECT_NE(error("  imu_spread: 1.5\n").find("field 'mismatch.imu_spread': must be below 1"),
            std::string::npos);
  EXPECT_NE(error("  gnss_covariance_scale: [2.0, 0.5]\n").find("0 < min <= max"),
            std::string::npos);
  EXPECT_NE(error("  gnss_slow_error_scale: [0.0, 2.0]\n").find("0 < min <= max"),
            std::string::npos);
  EXPECT_NE(error("  clock_offset_sigma_s: -1\n").find("must be a finite number >= 0"),
            std::string::npos);
}

}  // namespace
}  // namespace statebench::sim
