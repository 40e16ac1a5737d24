#include "simulator/scenario.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "estimator/estimator_config.hpp"
#include "simulator/scenario_sensors.hpp"
#include "sumo_test_support.hpp"

namespace statebench::sim {
namespace {

using testing::GridScenarioParts;
using testing::InputErrorOf;
using testing::TempDir;
using testing::WriteFile;

// Expects an InputError naming "<file>:<line>:" and the field, plus `what`.
void ExpectError(const std::string& message, const std::string& file_line, const std::string& field,
                 const std::string& what) {
  ASSERT_FALSE(message.empty()) << "no InputError thrown";
  EXPECT_NE(message.find(file_line), std::string::npos) << message;
  EXPECT_NE(message.find("field '" + field + "'"), std::string::npos) << message;
  EXPECT_NE(message.find(what), std::string::npos) << message;
}

TEST(Scenario, ParsesEveryField) {
  TempDir dir;
  const std::string text =
      "name: full\n"
      "seed: 9223372036854775807\n"
      "duration_s: 90.5\n"
      "origin: {latitude_deg: 48.5, longitude_deg: -2.25, altitude_m: 12.0}\n"
      "vehicle: shuttle.yaml\n"
      "network:\n"
      "  generate:\n"
      "    spider: {arm_number: 5, circle_number: 2, space_radius_m: 80.0, omit_center: true}\n"
      "    lanes: 2\n"
      "    lane_width_m: 3.5\n"
      "    speed_mps: 8.0\n"
      "    traffic_lights: true\n"
      "    tls_cycle_s: 50\n"
      "    elevation: {sigma_m: 0.5}\n"
      "    seed: 4\n"
      "ego:\n"
      "  from: a\n"
      "  to: b\n"
      "  via: [c, d]\n"
      "  loops: 2\n"
      "  depart_pos_m: 3.0\n"
      "  depart_speed_mps: 1.5\n"
      "  max_speed_mps: 5.0\n"
      "  car_follow_model: Krauss\n"
      "traffic:\n"
      "  density: 7\n"
      "  flows:\n"
      "    - {from: e, to: f, vehs_per_hour: 100, begin_s: 10, end_s: 20}\n"
      "    - {from: g, to: h, via: [i], vehs_per_hour: 50}\n"
      "sumo: {step_s: 0.05}\n"
      "sensors: setups/front_gnss.yaml\n"
      "faults: {gnss_outage: {from_s: 60}}\n";
  const Scenario s = LoadScenario(WriteFile(dir.path() / "full.yaml", text));
  EXPECT_EQ(s.name, "full");
  EXPECT_EQ(s.seed, 9223372036854775807ull);
  EXPECT_DOUBLE_EQ(s.duration_s, 90.5);
  EXPECT_DOUBLE_EQ(s.origin.latitude_deg, 48.5);
  EXPECT_DOUBLE_EQ(s.origin.longitude_deg, -2.25);
  EXPECT_DOUBLE_EQ(s.origin.altitude_m, 12.0);
  EXPECT_EQ(s.vehicle_file.filename(), "shuttle.yaml");
  EXPECT_TRUE(std::filesystem::is_regular_file(s.vehicle_file));
  ASSERT_TRUE(s.network.generate.has_value());
  EXPECT_FALSE(s.network.xml.has_value());
  const GeneratedNetwork& net = *s.network.generate;
  EXPECT_EQ(net.kind, GeneratedNetwork::Kind::kSpider);
  EXPECT_EQ(net.spider.arm_number, 5);
  EXPECT_EQ(net.spider.circle_number, 2);
  EXPECT_DOUBLE_EQ(net.spider.space_radius_m, 80.0);
  EXPECT_TRUE(net.spider.omit_center);
  EXPECT_EQ(net.lanes, 2);
  EXPECT_DOUBLE_EQ(net.lane_width_m, 3.5);
  EXPECT_DOUBLE_EQ(net.speed_mps, 8.0);
  EXPECT_TRUE(net.traffic_lights);
  EXPECT_EQ(net.tls_cycle_s, 50);
  EXPECT_DOUBLE_EQ(net.elevation_sigma_m, 0.5);
  EXPECT_DOUBLE_EQ(net.elevation_limit_m, 1.0);  // default: 2 sigma
  EXPECT_EQ(net.seed, 4u);
  EXPECT_TRUE(s.ego.route.empty());
  EXPECT_EQ(s.ego.from->edge_id, "a");
  EXPECT_EQ(s.ego.to->edge_id, "b");
  ASSERT_EQ(s.ego.via.size(), 2u);
  EXPECT_EQ(s.ego.via[1].edge_id, "d");
  EXPECT_EQ(s.ego.via[1].source.field, "ego.via[1]");
  EXPECT_EQ(s.ego.loops, 2);
  EXPECT_DOUBLE_EQ(s.ego.depart_pos_m, 3.0);
  EXPECT_DOUBLE_EQ(s.ego.depart_speed_mps, 1.5);
  EXPECT_DOUBLE_EQ(*s.ego.max_speed_mps, 5.0);
  EXPECT_EQ(s.ego.car_follow_model, "Krauss");
  EXPECT_EQ(s.traffic.density, 7);
  ASSERT_EQ(s.traffic.flows.size(), 2u);
  EXPECT_EQ(s.traffic.flows[0].from.edge_id, "e");
  EXPECT_DOUBLE_EQ(s.traffic.flows[0].begin_s, 10.0);
  EXPECT_DOUBLE_EQ(s.traffic.flows[0].end_s, 20.0);
  EXPECT_DOUBLE_EQ(s.traffic.flows[1].end_s, 90.5);  // default: the duration
  EXPECT_EQ(s.traffic.flows[1].via[0].edge_id, "i");
  EXPECT_DOUBLE_EQ(s.sumo.step_s, 0.05);
  ASSERT_TRUE(s.sensors.has_value());
  EXPECT_EQ(s.sensors->As<std::string>(), "setups/front_gnss.yaml");
  ASSERT_TRUE(s.faults.has_value());
  EXPECT_TRUE(s.faults->IsMap());
}

TEST(Scenario, AppliesDefaults) {
  TempDir dir;
  const Scenario s = LoadScenario(
      WriteFile(dir.path() / "min.yaml",
                "name: min\nseed: 1\nduration_s: 10\norigin: {latitude_deg: 1, longitude_deg: 2}\n"
                "vehicle: quadricycle\nnetwork: {generate: {grid: {}}}\nego: {route: [x]}\n"));
  EXPECT_EQ(s.vehicle_file.filename(), "quadricycle.yaml");
  EXPECT_DOUBLE_EQ(s.origin.altitude_m, 0.0);
  const GeneratedNetwork& net = *s.network.generate;
  EXPECT_EQ(net.kind, GeneratedNetwork::Kind::kGrid);
  EXPECT_EQ(net.grid.x_number, 5);
  EXPECT_DOUBLE_EQ(net.grid.y_length_m, 100.0);
  EXPECT_EQ(net.lanes, 1);
  EXPECT_FALSE(net.traffic_lights);
  EXPECT_DOUBLE_EQ(net.elevation_sigma_m, 0.0);
  EXPECT_EQ(s.ego.loops, 1);
  EXPECT_EQ(s.ego.car_follow_model, "IDM");
  EXPECT_DOUBLE_EQ(s.ego.depart_speed_mps, 0.0);
  EXPECT_FALSE(s.ego.max_speed_mps.has_value());
  EXPECT_EQ(s.traffic.density, 0);
  EXPECT_TRUE(s.traffic.flows.empty());
  EXPECT_DOUBLE_EQ(s.sumo.step_s, 0.1);
  EXPECT_FALSE(s.sensors.has_value());
  EXPECT_FALSE(s.faults.has_value());
}

TEST(Scenario, KeepsRouteEntryLocations) {
  TempDir dir;
  const Scenario s = LoadScenario(WriteFile(dir.path() / "grid.yaml", GridScenarioParts().Text()));
  ASSERT_EQ(s.ego.route.size(), 4u);
  EXPECT_EQ(s.ego.route[2].edge_id, "B1B0");
  EXPECT_EQ(s.ego.route[2].source.field, "ego.route[2]");
  // "  route: [A0A1, A1B1, B1B0, B0A0]" is line 14; B1B0 starts at column 23.
  EXPECT_EQ(s.ego.route[2].source.where, (dir.path() / "grid.yaml").string() + ":14:23");
}

TEST(Scenario, MissingFieldNamesFileLineAndField) {
  TempDir dir;
  GridScenarioParts parts;
  parts.header =
      "name: x\nseed: 1\norigin: {latitude_deg: 1, longitude_deg: 2}\nvehicle: shuttle\n";
  const auto file = WriteFile(dir.path() / "s.yaml", parts.Text());
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":1:", "duration_s",
              "missing field");
}

TEST(Scenario, WrongTypeNamesFileLineAndField) {
  TempDir dir;
  GridScenarioParts parts;
  parts.header =
      "name: x\nseed: 1\nduration_s: long\n"
      "origin: {latitude_deg: 1, longitude_deg: 2}\nvehicle: shuttle\n";
  const auto file = WriteFile(dir.path() / "s.yaml", parts.Text());
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":3:13", "duration_s",
              "expected a number, got 'long'");

  parts.header =
      "name: x\nseed: -3\nduration_s: 5\n"
      "origin: {latitude_deg: 1, longitude_deg: 2}\nvehicle: shuttle\n";
  WriteFile(file, parts.Text());
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":2:7", "seed",
              "non-negative integer");

  parts = GridScenarioParts();
  parts.ego = "ego:\n  route: A0A1\n";
  WriteFile(file, parts.Text());
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":14:10", "ego.route",
              "expected a list");
}

TEST(Scenario, UnknownFieldIsRejected) {
  TempDir dir;
  GridScenarioParts parts;
  parts.ego = "ego:\n  route: [A0A1]\n  loop: 2\n";
  const auto file = WriteFile(dir.path() / "s.yaml", parts.Text());
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":15:", "ego.loop",
              "unknown field");
}

TEST(Scenario, UnknownVehicleListsTheKnownOnes) {
  TempDir dir;
  GridScenarioParts parts;
  parts.header =
      "name: x\nseed: 1\nduration_s: 5\n"
      "origin: {latitude_deg: 1, longitude_deg: 2}\nvehicle: hovercraft.yaml\n";
  const auto file = WriteFile(dir.path() / "s.yaml", parts.Text());
  const std::string message = InputErrorOf([&] { LoadScenario(file); });
  ExpectError(message, file.string() + ":5:10", "vehicle", "unknown vehicle 'hovercraft.yaml'");
  EXPECT_NE(message.find("quadricycle"), std::string::npos) << message;
  EXPECT_NE(message.find("shuttle"), std::string::npos) << message;
}

TEST(Scenario, VehicleNextToTheScenarioWins) {
  TempDir dir;
  const auto local = WriteFile(dir.path() / "vehicles" / "quadricycle.yaml", "name: local\n");
  const auto found = FindVehicleFile(dir.path() / "sub", "quadricycle");
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(*found, std::filesystem::absolute(local).lexically_normal());
  EXPECT_FALSE(FindVehicleFile(dir.path(), "no_such_vehicle").has_value());
}

TEST(Scenario, RejectsInconsistentSections) {
  TempDir dir;
  const auto file = dir.path() / "s.yaml";
  struct Case {
    std::string network, ego, rest, file_line, field, what;
  };
  const GridScenarioParts base;
  const Case cases[] = {
      {base.network, "ego:\n  route: [A0A1]\n  from: A0A1\n", base.rest, ":14:", "ego",
       "either 'route'"},
      {base.network, "ego:\n  route: [A0A1]\n  loops: 0\n", base.rest, ":15:10", "ego.loops",
       "at least 1"},
      {base.network, "ego:\n  route: [A0A1]\n  car_follow_model: Wiedemann\n", base.rest,
       ":15:", "ego.car_follow_model", "IDM or Krauss"},
      {base.network, "ego:\n  route: [A0A1]\n  depart_speed_mps: 2.0\n  parked_s: 10.0\n",
       base.rest, ":16:", "ego.parked_s", "departs at 0 m/s"},
      {base.network, base.ego, "sumo:\n  step_s: 0.5\n", ":22:11", "sumo.step_s", "at most 0.1 s"},
      {"network:\n  generate: {grid: {}, spider: {}}\n", base.ego, base.rest, ":7:13",
       "network.generate", "exactly one of"},
      {"network:\n  generate: {grid: {}}\n  nodes: a.nod.xml\n", base.ego, base.rest, ":7:3",
       "network", "either 'generate'"},
      {"network:\n  nodes: missing.nod.xml\n  edges: missing.edg.xml\n", base.ego, base.rest,
       ":7:10", "network.nodes", "file not found"},
      {"network:\n  generate: {grid: {number: 0}}\n", base.ego, base.rest,
       ":7:", "network.generate.grid.number", "positive integer"},
  };
  for (const Case& c : cases) {
    GridScenarioParts parts;
    parts.network = c.network;
    parts.ego = c.ego;
    parts.rest = c.rest;
    WriteFile(file, parts.Text());
    SCOPED_TRACE(c.field);
    ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + c.file_line, c.field,
                c.what);
  }
}

TEST(Scenario, FlowNeedsAPositiveRateAndAnOrderedWindow) {
  TempDir dir;
  GridScenarioParts parts;
  parts.traffic = "traffic:\n  flows:\n    - {from: a, to: b, vehs_per_hour: 0}\n";
  const auto file = WriteFile(dir.path() / "s.yaml", parts.Text());
  ExpectError(InputErrorOf([&] { LoadScenario(file); }),
              file.string() + ":19:", "traffic.flows[0].vehs_per_hour", "positive");
  parts.traffic =
      "traffic:\n  flows:\n    - {from: a, to: b, vehs_per_hour: 9, begin_s: 30, "
      "end_s: 20}\n";
  WriteFile(file, parts.Text());
  ExpectError(InputErrorOf([&] { LoadScenario(file); }),
              file.string() + ":19:", "traffic.flows[0].end_s", "after begin_s");
}

TEST(Scenario, PaperScenariosLoad) {
  const std::filesystem::path paper = "scenarios/paper";
  const Scenario s1 = LoadScenario(paper / "setup1_quadricycle.yaml");
  const Scenario s2 = LoadScenario(paper / "setup2_quadricycle.yaml");
  const Scenario s3 = LoadScenario(paper / "setup3_shuttle.yaml");
  EXPECT_EQ(s1.vehicle_file.filename(), "quadricycle.yaml");
  EXPECT_EQ(s3.vehicle_file.filename(), "shuttle.yaml");
  // Setups 1 and 2 are the same drive.
  EXPECT_EQ(s1.seed, s2.seed);
  ASSERT_EQ(s1.ego.route.size(), s2.ego.route.size());
  for (std::size_t i = 0; i < s1.ego.route.size(); ++i) {
    EXPECT_EQ(s1.ego.route[i].edge_id, s2.ego.route[i].edge_id);
  }
  EXPECT_EQ(s1.ego.loops, s2.ego.loops);
  EXPECT_EQ(s1.duration_s, s2.duration_s);
  EXPECT_GE(s1.duration_s, 180.0);
  EXPECT_LE(s1.duration_s, 300.0);
  EXPECT_TRUE(s1.network.generate->traffic_lights);
  EXPECT_GT(s1.network.generate->elevation_sigma_m, 0.0);
  EXPECT_GT(s1.traffic.density, 0);
  ASSERT_TRUE(s3.network.xml.has_value());
  EXPECT_LE(*s3.ego.max_speed_mps, 25.0 / 3.6 + 1e-9);
  EXPECT_GE(s3.duration_s, 100.0);
}

// A grid scenario whose `estimators:` list (line 23) is `list` (entries from line 24 on).
std::filesystem::path WriteWithEstimators(const TempDir& dir, const std::string& list) {
  GridScenarioParts parts;
  parts.rest = "sumo:\n  step_s: 0.1\nestimators:\n" + list;
  return WriteFile(dir.path() / "est.yaml", parts.Text());
}

TEST(Scenario, ParsesTheEstimatorsList) {
  TempDir dir;
  WriteFile(dir.path() / "options" / "fg.yaml", "window_s: 2.0\n");
  const auto file =
      WriteWithEstimators(dir,
                          "  - {name: fg_w0.5, type: factor_graph, config: options/fg.yaml,\n"
                          "     overrides: {window_s: 0.5, gnss: {max_sigma_m: 3.0}}}\n"
                          "  - ekf\n"
                          "  - {type: factor_graph}\n");
  const Scenario s = LoadScenario(file);
  ASSERT_EQ(s.estimators.size(), 3u);
  EXPECT_EQ(s.estimators[0].label, "fg_w0.5");
  EXPECT_EQ(s.estimators[0].type, "factor_graph");
  EXPECT_EQ(s.estimators[0].config, dir.path() / "options" / "fg.yaml");
  ASSERT_TRUE(s.estimators[0].overrides.has_value());
  EXPECT_EQ(s.estimators[0].source.where, file.string() + ":24:5");
  EXPECT_EQ(s.estimators[0].source.field, "estimators[0]");
  // Shorthand and defaults: labelled by type, the stock options file of the type.
  EXPECT_EQ(s.estimators[1].label, "ekf");
  EXPECT_EQ(s.estimators[1].type, "ekf");
  EXPECT_EQ(s.estimators[1].config.filename(), "ekf.yaml");
  EXPECT_TRUE(std::filesystem::is_regular_file(s.estimators[1].config));
  EXPECT_FALSE(s.estimators[1].overrides.has_value());
  EXPECT_EQ(s.estimators[2].label, "factor_graph");
  EXPECT_EQ(s.estimators[2].config.filename(), "factor_graph.yaml");
  EXPECT_EQ(ScenarioEstimators(s).size(), 3u);
}

TEST(Scenario, WithoutEstimatorsListRunsFactorGraphAndEkf) {
  TempDir dir;
  const Scenario s = LoadScenario(WriteFile(dir.path() / "s.yaml", GridScenarioParts().Text()));
  EXPECT_TRUE(s.estimators.empty());
  const std::vector<EstimatorSpec> specs = ScenarioEstimators(s);
  ASSERT_EQ(specs.size(), 2u);
  EXPECT_EQ(specs[0].label, "factor_graph");
  EXPECT_EQ(specs[1].label, "ekf");
  EXPECT_EQ(specs[1].config.filename(), "ekf.yaml");
}

TEST(Scenario, EstimatorErrorsNameFileLineAndField) {
  TempDir dir;
  auto file = WriteWithEstimators(dir, "  - factor_graph\n  - {name: x, type: kalman}\n");
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":25:21",
              "estimators[1].type", "unknown estimator type 'kalman' (known: factor_graph, ekf)");

  file =
      WriteWithEstimators(dir, "  - {name: fg, type: factor_graph}\n  - {name: fg, type: ekf}\n");
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":25:12",
              "estimators[1].name",
              "duplicate estimator name 'fg' (also estimators[0] at " + file.string() + ":24:5)");

  file = WriteWithEstimators(dir, "  - ekf\n  - ekf\n");
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":25:5", "estimators[1]",
              "duplicate estimator name 'ekf'");

  file = WriteWithEstimators(dir, "  - {type: factor_graph, overrides: [window_s, 0.5]}\n");
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":24:37",
              "estimators[0].overrides", "expected a map of option overrides");

  file = WriteWithEstimators(dir, "  - {type: ekf, config: nowhere/ekf.yaml}\n");
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":24:25",
              "estimators[0].config", "no such estimator options file");

  file = WriteWithEstimators(dir, "  - {name: ../up, type: ekf}\n");
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":24:12",
              "estimators[0].name", "cannot name an output folder");

  file = WriteWithEstimators(dir, "  - {type: ekf, window_s: 0.5}\n");
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":24:17",
              "estimators[0].window_s", "unknown field");

  file = WriteWithEstimators(dir, "  []\n");
  ExpectError(InputErrorOf([&] { LoadScenario(file); }), file.string() + ":24:3", "estimators",
              "empty list");
}

// 1-based number of the line of `text` that starts with `prefix`, 0 if none.
int LineStartingWith(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.rfind(prefix, 0) == 0) return n;
  }
  return 0;
}

TEST(Scenario, EstimatorConfigMergesOverridesOverTheOptionsFile) {
  TempDir dir;
  WriteFile(dir.path() / "fg.yaml",
            "window_s: 2.0\nimu_samples_per_state: 10\ngnss: {max_sigma_m: 5.0, gate_chi2: 9.0}\n");
  const auto file =
      WriteWithEstimators(dir,
                          "  - {name: a, type: factor_graph, config: fg.yaml,\n"
                          "     overrides: {window_s: 0.5, gnss: {max_sigma_m: 3.0}}}\n");
  const Scenario s = LoadScenario(file);
  const std::string text = EstimatorConfigText(s.estimators.at(0), s);
  EXPECT_NE(text.find("estimator 'a' (factor_graph)"), std::string::npos) << text;
  EXPECT_NE(text.find(file.string() + ":24:5"), std::string::npos) << text;
  const auto written = WriteFile(dir.path() / "out" / "estimator_config.yaml", text);
  const est::FactorGraphOptions options = est::LoadFactorGraphOptions(written);
  EXPECT_DOUBLE_EQ(options.window_s, 0.5);
  EXPECT_EQ(options.imu_samples_per_state, 10);
  EXPECT_DOUBLE_EQ(options.gnss.max_sigma, 3.0);
  EXPECT_DOUBLE_EQ(options.gnss.gate_chi2, 9.0);
}

TEST(Scenario, BadOverrideValueFailsAtTheLineOfTheWrittenConfig) {
  TempDir dir;
  const auto file = WriteWithEstimators(
      dir, "  - {name: a, type: factor_graph, overrides: {imu_samples_per_state: many}}\n");
  const Scenario s = LoadScenario(file);
  const std::string text = EstimatorConfigText(s.estimators.at(0), s);
  const int line = LineStartingWith(text, "imu_samples_per_state: many");
  ASSERT_GT(line, 0) << text;
  const auto written = WriteFile(dir.path() / "out" / "estimator_config.yaml", text);
  ExpectError(InputErrorOf([&] { est::LoadFactorGraphOptions(written); }),
              written.string() + ":" + std::to_string(line) + ":", "imu_samples_per_state", "many");
}

TEST(Scenario, PaperScenariosNameTheirEstimators) {
  const std::filesystem::path paper = "scenarios/paper";
  const Scenario s1 = LoadScenario(paper / "setup1_quadricycle.yaml");
  // Windows 0.5, 1, 1.5, 2 s, each with and without the kinematic factor, and the EKF.
  ASSERT_EQ(s1.estimators.size(), 9u);
  int factor_graphs = 0;
  for (const EstimatorSpec& spec : s1.estimators) {
    factor_graphs += spec.type == "factor_graph";
    if (spec.type == "factor_graph") {
      EXPECT_TRUE(spec.overrides.has_value()) << spec.label;
    }
  }
  EXPECT_EQ(factor_graphs, 8);
  for (const char* name : {"setup2_quadricycle", "setup3_shuttle", "setup3_shuttle_rtk"}) {
    const Scenario s = LoadScenario(paper / (std::string(name) + ".yaml"));
    EXPECT_EQ(s.name, name);
    const std::vector<EstimatorSpec> specs = ScenarioEstimators(s);
    ASSERT_GE(specs.size(), 2u) << name;
    EXPECT_EQ(specs[0].type, "factor_graph") << name;
    EXPECT_EQ(specs[1].type, "ekf") << name;
    // Each names a sensor setup file, never a scenario file of the same name.
    EXPECT_EQ(std::filesystem::path(LoadScenarioSensors(s).setup.source).parent_path().filename(),
              "setups")
        << name;
  }
}

}  // namespace
}  // namespace statebench::sim
