// The sensor setup a scenario names, and its faults: the paper scenarios, file resolution,
// inline setups, and errors that name the file, line and field.
#include "simulator/scenario_sensors.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/geodetic.hpp"
#include "core/measurement_faults.hpp"

#include "sumo_test_support.hpp"

namespace statebench::sim {
namespace {

using testing::SourceDir;

using testing::GridScenarioParts;
using testing::InputErrorOf;
using testing::TempDir;
using testing::WriteFile;

const sensors::GnssOptions& Gnss(const ScenarioSensors& s, const std::string& id) {
  return std::get<sensors::GnssOptions>(s.setup.Find(id)->options);
}

// A grid scenario with the given `sensors:` and `faults:` lines, in `dir`.
Scenario GridWith(const TempDir& dir, const std::string& sensors_and_faults) {
  GridScenarioParts parts;
  parts.rest += sensors_and_faults;
  return LoadScenario(WriteFile(dir.path() / "town" / "grid.yaml", parts.Text()));
}

TEST(ScenarioSensors, PaperScenariosNameTheirSetupsAndSetup3LosesGnssAt60s) {
  for (const std::string name : {"setup1_quadricycle", "setup2_quadricycle", "setup3_shuttle"}) {
    const Scenario scenario = LoadScenario(SourceDir() / "scenarios/paper" / (name + ".yaml"));
    const ScenarioSensors s = LoadScenarioSensors(scenario);
    EXPECT_EQ(s.setup.name, name);  // the setup file, not the scenario of the same name
    EXPECT_EQ(std::filesystem::path(s.setup.source).parent_path().filename(), "setups");
    EXPECT_NE(s.setup_yaml.find("name: " + name), std::string::npos);
    EXPECT_FALSE(s.faults.urban_canyon.has_value());
  }
  const ScenarioSensors s3 =
      LoadScenarioSensors(LoadScenario(SourceDir() / "scenarios/paper/setup3_shuttle.yaml"));
  const auto& outages = Gnss(s3, "gnss_roof").outages;
  ASSERT_EQ(outages.size(), 1u);
  EXPECT_EQ(outages[0].start_s, 60.0);
  EXPECT_TRUE(std::isinf(outages[0].end_s));
  const ScenarioSensors s1 =
      LoadScenarioSensors(LoadScenario(SourceDir() / "scenarios/paper/setup1_quadricycle.yaml"));
  EXPECT_TRUE(Gnss(s1, "gnss_front").outages.empty());
}

TEST(ScenarioSensors, FindsSetupsLikeVehiclesAndAppliesFaults) {
  TempDir dir;
  // A setup next to the scenario wins over the stock one of the same name.
  WriteFile(dir.path() / "town" / "mine.yaml",
            "name: local_setup\nsensors:\n"
            "  - {type: gnss, id: ant_a, rate_hz: 5, latency_s: 0.1, mode: single,\n"
            "     T_body_sensor: {translation: [0, 0, 1.5]}}\n"
            "  - {type: gnss, id: ant_b, rate_hz: 5, latency_s: 0.1, mode: single,\n"
            "     T_body_sensor: {translation: [1, 0, 1.5]}}\n"
            "  - {type: speed_encoder, id: speed, rate_hz: 50, latency_s: 0.01,\n"
            "     distance_per_tick_m: 0.001, T_body_sensor: {translation: [0, 0, 0]}}\n");
  const ScenarioSensors local =
      LoadScenarioSensors(GridWith(dir,
                                   "sensors: mine\n"
                                   "faults:\n"
                                   "  gnss_outages:\n"
                                   "    - {start_s: 10.0, end_s: 20.0}\n"
                                   "    - {sensors: [ant_b], start_s: 30.0}\n"
                                   "  urban_canyon: {elevation_mask_deg: 15}\n"
                                   "  sensor_outages:\n"
                                   "    - {sensors: [speed, ant_a], start_s: 5.0, end_s: 8.0}\n"));
  EXPECT_EQ(local.setup.name, "local_setup");
  ASSERT_EQ(Gnss(local, "ant_a").outages.size(), 1u);
  ASSERT_EQ(Gnss(local, "ant_b").outages.size(), 2u);
  EXPECT_EQ(Gnss(local, "ant_b").outages[1].start_s, 30.0);
  ASSERT_TRUE(local.faults.urban_canyon.has_value());
  EXPECT_EQ(local.faults.urban_canyon->elevation_mask_deg, 15.0);
  ASSERT_EQ(local.faults.sensor_outages.size(), 1u);
  const SensorOutage& silent = local.faults.sensor_outages[0];
  EXPECT_TRUE(silent.Covers("speed", FromSeconds(5.0)));
  EXPECT_TRUE(silent.Covers("ant_a", FromSeconds(7.99)));
  EXPECT_FALSE(silent.Covers("speed", FromSeconds(8.0)));  // [start, end)
  EXPECT_FALSE(silent.Covers("ant_b", FromSeconds(6.0)));

  // Stock setups through scenarios/setups (STATEBENCH_SOURCE_DIR or the working folder).
  const ScenarioSensors stock = LoadScenarioSensors(
      GridWith(dir, "sensors: setup2_quadricycle\nfaults: {urban_canyon: true}\n"));
  EXPECT_EQ(stock.setup.name, "setup2_quadricycle");
  EXPECT_TRUE(stock.faults.urban_canyon.has_value());

  // An inline setup.
  const ScenarioSensors inline_setup = LoadScenarioSensors(
      GridWith(dir,
               "sensors:\n  name: inline\n  sensors:\n"
               "    - {type: imu, id: imu, rate_hz: 100, latency_s: 0, preset: tactical,\n"
               "       T_body_sensor: {translation: [0, 0, 0.5]}}\n"));
  EXPECT_EQ(inline_setup.setup.name, "inline");
  EXPECT_NE(inline_setup.setup_yaml.find("tactical"), std::string::npos);
}

TEST(ScenarioSensors, ErrorsNameFileLineAndField) {
  TempDir dir;
  const auto error = [&](const std::string& lines) {
    return InputErrorOf([&] { LoadScenarioSensors(GridWith(dir, lines)); });
  };
  EXPECT_NE(error("").find("field 'sensors': the scenario names no sensor setup"),
            std::string::npos);
  const std::string unknown = error("sensors: setup9\n");
  EXPECT_NE(unknown.find("grid.yaml:"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("field 'sensors': unknown sensor setup 'setup9'"), std::string::npos)
      << unknown;
  const std::string no_such = error(
      "sensors: setup3_shuttle\nfaults:\n  gnss_outages:\n    - {sensors: [gnss_x], start_s: 1}\n");
  EXPECT_NE(no_such.find("field 'faults.gnss_outages[0].sensors[0]': no sensor 'gnss_x'"),
            std::string::npos)
      << no_such;
  const std::string not_gnss = error(
      "sensors: setup3_shuttle\nfaults:\n  gnss_outages:\n    - {sensors: [imu], start_s: 1}\n");
  EXPECT_NE(not_gnss.find("'imu' is not a GNSS receiver"), std::string::npos) << not_gnss;
  const std::string order =
      error("sensors: setup3_shuttle\nfaults:\n  gnss_outages:\n    - {start_s: 5, end_s: 4}\n");
  EXPECT_NE(order.find("field 'faults.gnss_outages[0].end_s': must be after start_s"),
            std::string::npos)
      << order;
  EXPECT_NE(error("sensors: setup3_shuttle\nfaults:\n  sensor_outages:\n"
                  "    - {sensors: [lidar_top], start_s: 1}\n")
                .find("field 'faults.sensor_outages[0].sensors[0]': no sensor 'lidar_top'"),
            std::string::npos);
  EXPECT_NE(
      error("sensors: setup3_shuttle\nfaults: {gnss_outage: {start_s: 5}}\n").find("gnss_outage"),
      std::string::npos);
  EXPECT_NE(error("sensors: setup3_shuttle\nfaults: {urban_canyon: {elevation_mask_deg: 95}}\n")
                .find("field 'faults.urban_canyon.elevation_mask_deg': must be in [0, 90)"),
            std::string::npos);
}

TEST(ScenarioSensors, InjectedFaultsAreParsedCheckedAndActOnTheStream) {
  TempDir dir;
  const ScenarioSensors s = LoadScenarioSensors(
      GridWith(dir,
               "sensors: setup3_shuttle\n"
               "faults:\n"
               "  sensor_outages:\n"
               "    - {sensors: [imu], start_s: 50, end_s: 60}\n"
               "  injected:\n"
               "    - {type: gnss_jump, start_s: 40, end_s: 45, offset_m: [100, 0, 0]}\n"
               "    - {type: non_finite, sensors: [imu], start_s: 30, end_s: 31, value: -inf}\n"
               "    - {type: gnss_overconfident, start_s: 10, sigma_m: 0.01}\n"
               "    - {type: clock_jump, sensors: [gnss_roof], start_s: 1, shift_s: -1}\n"
               "    - {type: lidar_garbage, start_s: 1, end_s: 2, far_m: 1e6}\n"
               "    - {type: imu_saturation, start_s: 1, end_s: 2}\n"
               "    - {type: duplicate, start_s: 1, end_s: 2}\n"
               "    - {type: stamps_backwards, sensors: [imu], start_s: 1, end_s: 2}\n"));
  ASSERT_EQ(s.faults.injected.size(), 8u);
  const MeasurementFault& jump = s.faults.injected[0];
  EXPECT_EQ(jump.kind, MeasurementFaultKind::kGnssJump);
  EXPECT_TRUE(jump.sensors.empty());
  EXPECT_EQ(jump.offset_m, Vec3(100, 0, 0));
  EXPECT_EQ(s.faults.injected[1].value, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(s.faults.injected[2].offset_m, Vec3(20, 0, 0));  // default: 20 m off
  EXPECT_TRUE(std::isinf(s.faults.injected[2].end_s));
  EXPECT_EQ(s.faults.injected[3].shift_s, -1.0);
  EXPECT_EQ(s.faults.injected[4].far_m, 1e6);
  EXPECT_NEAR(s.faults.injected[5].accel_limit_mps2, 16 * 9.80665, 1e-9);
  // The stream's faults: the outage as a gap first, then the injected ones in order.
  const std::vector<MeasurementFault> stream = s.faults.StreamFaults();
  ASSERT_EQ(stream.size(), 9u);
  EXPECT_EQ(stream[0].kind, MeasurementFaultKind::kGap);
  EXPECT_EQ(stream[1].kind, MeasurementFaultKind::kGnssJump);

  // On measurements: a gap drops, a jump moves the fix, duplicate repeats, non-finite writes.
  MeasurementFaultInjector injector(stream);
  std::vector<Measurement> out;
  ImuSample imu;
  imu.header = {"imu", FromSeconds(55.0), FromSeconds(55.0)};
  injector.Apply(imu, &out);
  EXPECT_TRUE(out.empty());
  imu.header = {"imu", FromSeconds(30.5), FromSeconds(30.5)};
  injector.Apply(imu, &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(std::get<ImuSample>(out[0]).gyro.x(), -std::numeric_limits<double>::infinity());
  out.clear();
  GnssFix fix;
  fix.header = {"gnss_roof", FromSeconds(42.0), FromSeconds(42.1)};
  fix.latitude_deg = 48.7;
  fix.longitude_deg = 2.2;
  fix.covariance_enu = Mat3::Identity();
  injector.Apply(fix, &out);
  ASSERT_EQ(out.size(), 1u);
  const LocalEnuFrame frame({48.7, 2.2, 0.0});
  const auto& moved = std::get<GnssFix>(out[0]);
  const Vec3 d = frame.ToEnu({moved.latitude_deg, moved.longitude_deg, moved.altitude_m});
  EXPECT_NEAR(d.x(), 120.0, 1e-6);  // 100 m jump + 20 m overconfident offset
  EXPECT_NEAR(moved.covariance_enu(0, 0), 1e-4, 1e-12);
  EXPECT_EQ(moved.header.stamp_ns, FromSeconds(41.0));  // clock 1 s behind
  out.clear();
  imu.header = {"imu", FromSeconds(1.5), FromSeconds(1.5)};
  imu.accel = Vec3(0.1, -0.2, 9.8);
  injector.Apply(imu, &out);
  ASSERT_EQ(out.size(), 2u);  // duplicated
  const auto& rail = std::get<ImuSample>(out[1]);
  EXPECT_NEAR(rail.accel.y(), -16 * 9.80665, 1e-9);
  EXPECT_EQ(rail.header.stamp_ns, FromSeconds(0.5));  // stamped 1 s back
  ASSERT_EQ(injector.affected().size(), 9u);
  EXPECT_EQ(injector.affected()[0], 1u);  // the gap
  EXPECT_EQ(injector.affected()[1], 1u);  // the jump

  const auto error = [&](const std::string& entry) {
    return InputErrorOf([&] {
      LoadScenarioSensors(
          GridWith(dir, "sensors: setup3_shuttle\nfaults:\n  injected:\n    - " + entry + "\n"));
    });
  };
  EXPECT_NE(error("{type: melt, start_s: 1}").find("field 'faults.injected[0].type': unknown "
                                                  "fault type 'melt'"),
            std::string::npos);
  EXPECT_NE(error("{type: gnss_jump, sensors: [imu], start_s: 1}")
                .find("field 'faults.injected[0].sensors[0]': a gnss_jump fault does not apply "
                      "to 'imu' (sensor type imu)"),
            std::string::npos);
  EXPECT_NE(error("{type: duplicate, start_s: 1, sigma_m: 2}")
                .find("field 'faults.injected[0].sigma_m': not an option of a duplicate fault"),
            std::string::npos);
  EXPECT_NE(error("{type: non_finite, start_s: 1, value: banana}").find("value"),
            std::string::npos);
  EXPECT_NE(error("{type: gnss_jump, start_s: 5, end_s: 1}")
                .find("field 'faults.injected[0].end_s': must be after start_s"),
            std::string::npos);
}

}  // namespace
}  // namespace statebench::sim
