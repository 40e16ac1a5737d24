#include "simulator/network_builder.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>

#include "simulator/traffic_demand.hpp"
#include "simulator/xml_scan.hpp"
#include "sumo_test_support.hpp"

namespace statebench::sim {
namespace {

using testing::GridScenarioParts;
using testing::InputErrorOf;
using testing::TempDir;
using testing::WriteFile;

struct Loaded {
  std::filesystem::path file;
  Scenario scenario;
};

Loaded LoadParts(const TempDir& dir, const GridScenarioParts& parts) {
  const auto file = WriteFile(dir.path() / "scenario.yaml", parts.Text());
  return {file, LoadScenario(file)};
}

int CountElements(const std::filesystem::path& file, const std::string& name) {
  int n = 0;
  ForEachXmlElement(ReadTextFile(file), [&](const XmlElement& e) { n += e.name == name; });
  return n;
}

TEST(NetworkBuilder, BuildsAGeneratedGridWithLightsAndRoutes) {
  TempDir dir;
  const Loaded in = LoadParts(dir, GridScenarioParts());
  const BuiltNetwork built =
      NetworkBuilder().Build(in.scenario, EgoVehicleType(), dir.path() / "out");
  EXPECT_TRUE(std::filesystem::is_regular_file(built.net_file));
  EXPECT_TRUE(built.index.HasEdge("A0A1"));
  EXPECT_TRUE(built.index.HasEdge("left1A1"));
  EXPECT_FALSE(built.index.HasEdge(":A1_0"));  // internal edges are not route edges
  EXPECT_TRUE(built.index.Connected("A0A1", "A1B1"));
  EXPECT_FALSE(built.index.Connected("A0A1", "B1B0"));
  EXPECT_EQ(built.index.net_offset, Vec2::Zero());
  // Lights at the 9 grid junctions (3 or 4 roads), none at the 12 dead ends.
  EXPECT_EQ(CountElements(built.net_file, "tlLogic"), 9);
  // Three loops of the four-edge block.
  ASSERT_EQ(built.ego_route.size(), 12u);
  EXPECT_EQ(built.ego_route[4], "A0A1");
  EXPECT_EQ(built.ego_route[11], "B0A0");
  // Routes file: the ego's vType, route and vehicle, then the flow's trips.
  int egos = 0;
  int trips = 0;
  double last_depart = -1.0;
  ForEachXmlElement(ReadTextFile(built.routes_file), [&](const XmlElement& e) {
    if (e.name == "vType" && e.Attribute("id") == "ego_type") {
      EXPECT_EQ(e.Attribute("length"), "2.34");
      EXPECT_EQ(e.Attribute("sigma"), "0");
      EXPECT_EQ(e.Attribute("carFollowModel"), "IDM");
    }
    if (e.name == "vehicle") {
      ++egos;
      EXPECT_EQ(e.Attribute("id"), "ego");
      EXPECT_EQ(e.Attribute("departPos"), "5");
    }
    if (e.name == "trip") {
      ++trips;
      const double depart = std::stod(e.Attribute("depart"));
      EXPECT_GE(depart, last_depart);
      last_depart = depart;
      EXPECT_EQ(e.Attribute("from"), "left1A1");
    }
  });
  EXPECT_EQ(egos, 1);
  // 400 vehicles/h for 40 s: 4.4 expected; a Poisson count stays well below 20.
  EXPECT_GT(trips, 0);
  EXPECT_LT(trips, 20);
}

TEST(NetworkBuilder, SameScenarioSameFiles) {
  TempDir dir;
  const Loaded in = LoadParts(dir, GridScenarioParts());
  const BuiltNetwork a = NetworkBuilder().Build(in.scenario, EgoVehicleType(), dir.path() / "a");
  const BuiltNetwork b = NetworkBuilder().Build(in.scenario, EgoVehicleType(), dir.path() / "b");
  EXPECT_EQ(ReadTextFile(a.routes_file), ReadTextFile(b.routes_file));
  EXPECT_EQ(a.index.edges, b.index.edges);
  EXPECT_EQ(a.index.edge_length_m, b.index.edge_length_m);
  EXPECT_EQ(a.ego_route, b.ego_route);
}

TEST(NetworkBuilder, MissingRouteEdgeNamesTheRouteEntry) {
  TempDir dir;
  GridScenarioParts parts;
  parts.ego = "ego:\n  route: [A0A1, A1B1,\n          B1Z0, B0A0]\n";
  const Loaded in = LoadParts(dir, parts);
  const std::string message = InputErrorOf(
      [&] { NetworkBuilder().Build(in.scenario, EgoVehicleType(), dir.path() / "out"); });
  EXPECT_NE(message.find(in.file.string() + ":15:11"), std::string::npos) << message;
  EXPECT_NE(message.find("field 'ego.route[2]'"), std::string::npos) << message;
  EXPECT_NE(message.find("edge 'B1Z0' is not in the network"), std::string::npos) << message;
}

TEST(NetworkBuilder, DisconnectedRouteAndOpenLoopAreRejected) {
  TempDir dir;
  GridScenarioParts parts;
  parts.ego = "ego:\n  route: [A0A1, B1B0]\n";
  Loaded in = LoadParts(dir, parts);
  std::string message = InputErrorOf(
      [&] { NetworkBuilder().Build(in.scenario, EgoVehicleType(), dir.path() / "out"); });
  EXPECT_NE(message.find(":14:17"), std::string::npos) << message;
  EXPECT_NE(message.find("'B1B0' does not follow 'A0A1'"), std::string::npos) << message;

  parts.ego = "ego:\n  route: [A0A1, A1B1]\n  loops: 2\n";
  in = LoadParts(dir, parts);
  message = InputErrorOf(
      [&] { NetworkBuilder().Build(in.scenario, EgoVehicleType(), dir.path() / "out"); });
  EXPECT_NE(message.find(":15:10"), std::string::npos) << message;
  EXPECT_NE(message.find("field 'ego.loops'"), std::string::npos) << message;
  EXPECT_NE(message.find("cannot loop"), std::string::npos) << message;
}

TEST(NetworkBuilder, UnknownFlowEdgeAndFarDepartureAreRejected) {
  TempDir dir;
  GridScenarioParts parts;
  parts.traffic = "traffic:\n  flows:\n    - {from: left1A1, to: nowhere, vehs_per_hour: 60}\n";
  Loaded in = LoadParts(dir, parts);
  std::string message = InputErrorOf(
      [&] { NetworkBuilder().Build(in.scenario, EgoVehicleType(), dir.path() / "out"); });
  EXPECT_NE(message.find(":19:"), std::string::npos) << message;
  EXPECT_NE(message.find("field 'traffic.flows[0].to'"), std::string::npos) << message;

  parts = GridScenarioParts();
  parts.ego = "ego:\n  route: [A0A1]\n  depart_pos_m: 500\n";
  in = LoadParts(dir, parts);
  message = InputErrorOf(
      [&] { NetworkBuilder().Build(in.scenario, EgoVehicleType(), dir.path() / "out"); });
  EXPECT_NE(message.find("depart_pos_m 500 m is beyond"), std::string::npos) << message;
}

TEST(NetworkBuilder, MissingToolsAreNamedWithTheScenarioField) {
  TempDir dir;
  const Loaded grid = LoadParts(dir, GridScenarioParts());
  const NetworkBuilder no_tools(SumoTools::FindIn((dir.path() / "empty").string()));
  std::string message =
      InputErrorOf([&] { no_tools.Build(grid.scenario, EgoVehicleType(), dir.path() / "out"); });
  EXPECT_NE(message.find(grid.file.string() + ":7:3"), std::string::npos) << message;
  EXPECT_NE(message.find("field 'network'"), std::string::npos) << message;
  EXPECT_NE(message.find("netgenerate not found"), std::string::npos) << message;
  EXPECT_NE(message.find("install the Debian package sumo (scripts/setup.sh)"), std::string::npos)
      << message;

  const Scenario campus = LoadScenario("scenarios/paper/setup3_shuttle.yaml");
  message = InputErrorOf([&] { no_tools.Build(campus, EgoVehicleType(), dir.path() / "out"); });
  EXPECT_NE(message.find("setup3_shuttle.yaml:"), std::string::npos) << message;
  EXPECT_NE(message.find("netconvert not found"), std::string::npos) << message;

  GridScenarioParts routed;
  routed.ego = "ego:\n  from: A0A1\n  to: B0A0\n";
  const Loaded r = LoadParts(dir, routed);
  SumoTools no_router = SumoTools::Find();
  no_router.duarouter.clear();
  message = InputErrorOf(
      [&] { NetworkBuilder(no_router).Build(r.scenario, EgoVehicleType(), dir.path() / "out"); });
  EXPECT_NE(message.find(r.file.string() + ":14:9"), std::string::npos) << message;
  EXPECT_NE(message.find("field 'ego.from'"), std::string::npos) << message;
  EXPECT_NE(message.find("duarouter not found"), std::string::npos) << message;
}

TEST(NetworkBuilder, FailingToolReportsItsOutput) {
  TempDir dir;
  const Loaded grid = LoadParts(dir, GridScenarioParts());
  const auto fake = WriteFile(dir.path() / "bin" / "netgenerate",
                              "#!/bin/sh\necho 'Error: the grid is on fire' >&2\nexit 3\n");
  ::chmod(fake.c_str(), 0755);
  const NetworkBuilder builder(SumoTools::FindIn((dir.path() / "bin").string()));
  const std::string message =
      InputErrorOf([&] { builder.Build(grid.scenario, EgoVehicleType(), dir.path() / "out"); });
  EXPECT_NE(message.find(grid.file.string() + ":7:3"), std::string::npos) << message;
  EXPECT_NE(message.find("netgenerate failed (exit 3"), std::string::npos) << message;
  EXPECT_NE(message.find("the grid is on fire"), std::string::npos) << message;
}

TEST(NetworkBuilder, RoutesFromToThroughVia) {
  TempDir dir;
  GridScenarioParts parts;
  parts.ego = "ego:\n  from: A0A1\n  to: C2C1\n  via: [C1C2]\n";
  const Loaded in = LoadParts(dir, parts);
  const BuiltNetwork built =
      NetworkBuilder().Build(in.scenario, EgoVehicleType(), dir.path() / "out");
  ASSERT_GE(built.ego_route.size(), 3u);
  EXPECT_EQ(built.ego_route.front(), "A0A1");
  EXPECT_EQ(built.ego_route.back(), "C2C1");
  EXPECT_NE(std::find(built.ego_route.begin(), built.ego_route.end(), "C1C2"),
            built.ego_route.end());
  for (std::size_t i = 1; i < built.ego_route.size(); ++i) {
    EXPECT_TRUE(built.index.Connected(built.ego_route[i - 1], built.ego_route[i]))
        << built.ego_route[i - 1] << " -> " << built.ego_route[i];
  }
}

TEST(NetworkBuilder, NetconvertKeepsTheXmlCoordinates) {
  TempDir dir;
  const Scenario campus = LoadScenario("scenarios/paper/setup3_shuttle.yaml");
  const BuiltNetwork built = NetworkBuilder().Build(campus, EgoVehicleType(), dir.path());
  EXPECT_EQ(built.index.net_offset, Vec2::Zero());
  EXPECT_TRUE(built.index.HasEdge("n4_n5"));
  EXPECT_EQ(CountElements(built.net_file, "tlLogic"), 1);
  // Node n4 is at (100, 225, 4) in campus.nod.xml; the built junction keeps those coordinates.
  bool found = false;
  ForEachXmlElement(ReadTextFile(built.net_file), [&](const XmlElement& e) {
    if (e.name == "junction" && e.Attribute("id") == "n4") {
      found = true;
      EXPECT_DOUBLE_EQ(std::stod(e.Attribute("x")), 100.0);
      EXPECT_DOUBLE_EQ(std::stod(e.Attribute("y")), 225.0);
      EXPECT_DOUBLE_EQ(std::stod(e.Attribute("z")), 4.0);
    }
  });
  EXPECT_TRUE(found);
  EXPECT_EQ(built.ego_route.size(), 12u);
}

TEST(EgoVehicleType, ComesFromTheVehicleFiles) {
  for (const char* name : {"quadricycle", "shuttle"}) {
    const VehicleParams vehicle =
        LoadVehicleParamsFile(std::string("scenarios/vehicles/") + name + ".yaml");
    const EgoVehicleType type = EgoVehicleTypeFor(vehicle);
    std::string why;
    EXPECT_TRUE(type.IsValid(&why)) << name << ": " << why;
    EXPECT_EQ(type.length_m, vehicle.body.length_m);
    EXPECT_EQ(type.height_m, vehicle.body.height_m);
    EXPECT_EQ(type.max_speed_mps, vehicle.max_speed_mps);
    EXPECT_EQ(type.max_decel_mps2, vehicle.max_deceleration_mps2);
    EXPECT_GT(type.emergency_decel_mps2, type.max_decel_mps2);
  }
  EgoVehicleType bad;
  bad.width_m = 0.0;
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("dimensions"), std::string::npos);
}

TEST(TrafficDemand, FlowTripsAreSeededPoissonArrivals) {
  TrafficSpec traffic;
  FlowSpec flow;
  flow.from.edge_id = "a";
  flow.to.edge_id = "b";
  flow.vehs_per_hour = 720.0;  // one every 5 s on average
  flow.begin_s = 100.0;
  flow.end_s = 1e9;
  traffic.flows = {flow};
  const std::vector<Trip> a = FlowTrips(traffic, 5, 3700.0);
  const std::vector<Trip> b = FlowTrips(traffic, 5, 3700.0);
  const std::vector<Trip> c = FlowTrips(traffic, 6, 3700.0);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].depart_s, b[i].depart_s);
    EXPECT_EQ(a[i].type_id, b[i].type_id);
  }
  ASSERT_FALSE(c.empty());
  EXPECT_NE(a.front().depart_s, c.front().depart_s);
  // 720 expected over 3600 s; Poisson sigma 27: within 5 sigma.
  EXPECT_NEAR(static_cast<double>(a.size()), 720.0, 135.0);
  EXPECT_GE(a.front().depart_s, 100.0);
  EXPECT_LT(a.back().depart_s, 3700.0);
  int buses = 0;
  for (const Trip& t : a) buses += t.type_id == "traffic_bus";
  EXPECT_GT(buses, 10);  // 5 % of ~720
  EXPECT_LT(buses, 80);
}

}  // namespace
}  // namespace statebench::sim
