#include "simulator/scenario.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace statebench::sim
