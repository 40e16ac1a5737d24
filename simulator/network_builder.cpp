#include "simulator/network_builder.hpp"

#include <fstream>

#include "simulator/routes_file.hpp"
#include "simulator/traffic_demand.hpp"
#include "simulator/xml_scan.hpp"

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;

const fs::path& RequireTool(const fs::path& tool, const std::string& name,
                            const SourceRef& source) {
  if (tool.empty()) {
    source.Fail(name + " not found (searched PATH and $SUMO_HOME/bin): install the Debian " +
                "package sumo (scripts/setup.sh)");
  }
  return tool;
}

void RunOrFail(const fs::path& tool, const std::vector<std::string>& args, const fs::path& log_file,
               const SourceRef& source) {
  const ToolRun run = RunTool(tool, args, log_file);
  if (run.exit_code != 0) {
    source.Fail(tool.filename().string() + " failed (exit " + std::to_string(run.exit_code) +
                ", log " + log_file.string() + "):\n" + run.log_tail);
  }
}

void RequireEdge(const NetIndex& index, const RouteEdge& edge) {
  if (!index.HasEdge(edge.edge_id)) {
    edge.source.Fail("edge '" + edge.edge_id + "' is not in the network");
  }
}

// Explicit route: every edge exists and follows its predecessor through a connection.
void CheckExplicitRoute(const EgoSpec& ego, const NetIndex& index) {
  for (std::size_t i = 0; i < ego.route.size(); ++i) {
    RequireEdge(index, ego.route[i]);
    if (i > 0 && !index.Connected(ego.route[i - 1].edge_id, ego.route[i].edge_id)) {
      ego.route[i].source.Fail("edge '" + ego.route[i].edge_id + "' does not follow '" +
                               ego.route[i - 1].edge_id + "': no connection between them");
    }
  }
}

// duarouter's route for a from/to(/via) trip.
std::vector<std::string> ReadRoutedEdges(const fs::path& routes_file) {
  std::vector<std::string> edges;
  ForEachXmlElement(ReadTextFile(routes_file), [&](const XmlElement& e) {
    if (e.name != "route" || !edges.empty()) return;
    std::string edge;
    for (const char c : e.Attribute("edges") + " ") {
      if (c != ' ') {
        edge.push_back(c);
      } else if (!edge.empty()) {
        edges.push_back(edge);
        edge.clear();
      }
    }
  });
  return edges;
}

}  // namespace

std::vector<std::string> NetgenerateArguments(const GeneratedNetwork& net) {
  std::vector<std::string> args;
  const auto add = [&](const std::string& key, const std::string& value) {
    args.push_back(key);
    args.push_back(value);
  };
  switch (net.kind) {
    case GeneratedNetwork::Kind::kGrid:
      args.push_back("--grid");
      add("--grid.x-number", std::to_string(net.grid.x_number));
      add("--grid.y-number", std::to_string(net.grid.y_number));
      add("--grid.x-length", FormatNumber(net.grid.x_length_m));
      add("--grid.y-length", FormatNumber(net.grid.y_length_m));
      add("--grid.attach-length", FormatNumber(net.grid.attach_length_m));
      break;
    case GeneratedNetwork::Kind::kSpider:
      args.push_back("--spider");
      add("--spider.arm-number", std::to_string(net.spider.arm_number));
      add("--spider.circle-number", std::to_string(net.spider.circle_number));
      add("--spider.space-radius", FormatNumber(net.spider.space_radius_m));
      if (net.spider.omit_center) args.push_back("--spider.omit-center");
      break;
    case GeneratedNetwork::Kind::kRandom:
      args.push_back("--rand");
      add("--rand.iterations", std::to_string(net.random.iterations));
      add("--rand.min-distance", FormatNumber(net.random.min_distance_m));
      add("--rand.max-distance", FormatNumber(net.random.max_distance_m));
      add("--bidi-probability", FormatNumber(net.random.bidi_probability));
      break;
  }
  add("--default.lanenumber", std::to_string(net.lanes));
  add("--default.lanewidth", FormatNumber(net.lane_width_m));
  add("--default.speed", FormatNumber(net.speed_mps));
  if (net.traffic_lights) {
    // Lights where the incoming lane speeds sum above 2.5 roads' worth: every junction of three
    // or more roads, never a dead end or a plain bend.
    args.push_back("--tls.guess");
    add("--tls.guess.threshold", FormatNumber(2.5 * net.lanes * net.speed_mps));
    if (net.tls_cycle_s > 0) add("--tls.cycle.time", std::to_string(net.tls_cycle_s));
  }
  if (net.elevation_sigma_m > 0.0) {
    add("--perturb-z", "normc(0," + FormatNumber(net.elevation_sigma_m) + "," +
                           FormatNumber(-net.elevation_limit_m) + "," +
                           FormatNumber(net.elevation_limit_m) + ")");
  }
  add("--seed", std::to_string(SumoSeed(net.seed, "netgenerate")));
  return args;
}

fs::path NetworkBuilder::BuildNet(const NetworkSpec& spec, const fs::path& work_dir) const {
  const fs::path net_file = work_dir / "net.net.xml";
  if (spec.generate) {
    const fs::path& tool = RequireTool(tools_.netgenerate, "netgenerate", spec.source);
    std::vector<std::string> args = NetgenerateArguments(*spec.generate);
    args.insert(args.end(), {"--output-file", net_file.string()});
    RunOrFail(tool, args, work_dir / "netgenerate.log", spec.source);
  } else {
    const fs::path& tool = RequireTool(tools_.netconvert, "netconvert", spec.source);
    const XmlNetwork& xml = *spec.xml;
    std::vector<std::string> args = {"--node-files",
                                     xml.nodes.string(),
                                     "--edge-files",
                                     xml.edges.string(),
                                     "--offset.disable-normalization",
                                     "--output-file",
                                     net_file.string()};
    if (xml.connections) args.insert(args.end(), {"--connection-files", xml.connections->string()});
    if (xml.traffic_lights) {
      args.insert(args.end(), {"--tllogic-files", xml.traffic_lights->string()});
    }
    RunOrFail(tool, args, work_dir / "netconvert.log", spec.source);
  }
  return net_file;
}

std::vector<std::string> NetworkBuilder::EgoRoute(const EgoSpec& ego, const NetIndex& index,
                                                  const fs::path& net_file,
                                                  const fs::path& work_dir) const {
  std::vector<std::string> once;
  if (!ego.route.empty()) {
    CheckExplicitRoute(ego, index);
    for (const RouteEdge& e : ego.route) once.push_back(e.edge_id);
  } else {
    RequireEdge(index, *ego.from);
    RequireEdge(index, *ego.to);
    for (const RouteEdge& v : ego.via) RequireEdge(index, v);
    const fs::path& tool = RequireTool(tools_.duarouter, "duarouter", ego.from->source);
    const fs::path trip_file = work_dir / "ego_trip.xml";
    {
      std::ofstream trip(trip_file);
      trip << "<routes>\n  <trip id=\"ego\" depart=\"0\" from=\"" << XmlEscape(ego.from->edge_id)
           << "\" to=\"" << XmlEscape(ego.to->edge_id) << "\"";
      if (!ego.via.empty()) {
        std::string via;
        for (const RouteEdge& v : ego.via) {
          if (!via.empty()) via += ' ';
          via += XmlEscape(v.edge_id);
        }
        trip << " via=\"" << via << "\"";
      }
      trip << "/>\n</routes>\n";
    }
    const fs::path routed_file = work_dir / "ego_route.rou.xml";
    RunOrFail(tool,
              {"--net-file", net_file.string(), "--route-files", trip_file.string(),
               "--output-file", routed_file.string(), "--no-step-log", "--seed", "1"},
              work_dir / "duarouter.log", ego.from->source);
    once = ReadRoutedEdges(routed_file);
    if (once.empty())
      ego.from->source.Fail("duarouter found no route to '" + ego.to->edge_id + "'");
  }
  if (ego.loops > 1 && !index.Connected(once.back(), once.front())) {
    ego.loops_source.Fail("the route cannot loop: its last edge '" + once.back() +
                          "' does not connect to its first edge '" + once.front() + "'");
  }
  std::vector<std::string> route;
  for (int k = 0; k < ego.loops; ++k) route.insert(route.end(), once.begin(), once.end());
  return route;
}

BuiltNetwork NetworkBuilder::Build(const Scenario& scenario, const EgoVehicleType& ego_type,
                                   const fs::path& work_dir) const {
  std::string why;
  if (!ego_type.IsValid(&why)) throw InputError(scenario.vehicle_file.string() + ": " + why);
  BuiltNetwork built;
  built.work_dir = fs::absolute(work_dir);
  fs::create_directories(built.work_dir);
  built.net_file = BuildNet(scenario.network, built.work_dir);
  try {
    built.index = ReadNetIndex(built.net_file);
  } catch (const std::exception& e) {
    scenario.network.source.Fail(std::string("the built network is unreadable: ") + e.what());
  }
  built.ego_route = EgoRoute(scenario.ego, built.index, built.net_file, built.work_dir);
  const double first_edge_m = built.index.edge_length_m.count(built.ego_route.front()) > 0
                                  ? built.index.edge_length_m.at(built.ego_route.front())
                                  : 0.0;
  if (scenario.ego.depart_pos_m >= first_edge_m) {
    scenario.ego.source.Fail("depart_pos_m " + FormatNumber(scenario.ego.depart_pos_m) +
                             " m is beyond the first route edge '" + built.ego_route.front() +
                             "' (" + FormatNumber(first_edge_m) + " m long)");
  }
  for (const FlowSpec& flow : scenario.traffic.flows) {
    RequireEdge(built.index, flow.from);
    RequireEdge(built.index, flow.to);
    for (const RouteEdge& v : flow.via) RequireEdge(built.index, v);
  }
  built.routes_file = built.work_dir / "routes.rou.xml";
  WriteRoutesFile(built.routes_file, scenario.ego, ego_type, built.ego_route,
                  FlowTrips(scenario.traffic, scenario.seed, scenario.duration_s));
  return built;
}

}  // namespace statebench::sim
