#include "simulator/scenario.hpp"

#include <algorithm>
#include <cstdlib>
#include <set>

#include "simulator/scenario_parsing.hpp"

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;

GeodeticPoint ParseOrigin(const YamlNode& node) {
  node.ExpectOnlyKeys({"latitude_deg", "longitude_deg", "altitude_m"});
  GeodeticPoint origin;
  origin.latitude_deg = GetInRange(node, "latitude_deg", -90.0, 90.0);
  origin.longitude_deg = GetInRange(node, "longitude_deg", -180.0, 180.0);
  origin.altitude_m = node.Get<double>("altitude_m", 0.0);
  return origin;
}

// $STATEBENCH_SOURCE_DIR/scenarios/vehicles, then ./scenarios/vehicles (the repository root
// when run from there).
std::vector<fs::path> FallbackVehicleDirs() {
  std::vector<fs::path> dirs;
  if (const char* source_dir = std::getenv("STATEBENCH_SOURCE_DIR")) {
    dirs.push_back(fs::path(source_dir) / "scenarios" / "vehicles");
  }
  std::error_code ec;
  const fs::path cwd = fs::current_path(ec);
  if (!ec) dirs.push_back(cwd / "scenarios" / "vehicles");
  return dirs;
}

std::vector<std::string> KnownVehicles(const fs::path& scenario_dir) {
  std::set<std::string> names;
  std::vector<fs::path> dirs;
  for (fs::path dir = fs::absolute(scenario_dir.empty() ? fs::path(".") : scenario_dir);
       !dir.empty(); dir = dir.parent_path()) {
    dirs.push_back(dir / "vehicles");
    dirs.push_back(dir / "scenarios" / "vehicles");
    if (dir == dir.parent_path()) break;
  }
  const std::vector<fs::path> fallback = FallbackVehicleDirs();
  dirs.insert(dirs.end(), fallback.begin(), fallback.end());
  std::error_code ec;
  for (const fs::path& dir : dirs) {
    if (!fs::is_directory(dir, ec)) continue;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      if (entry.path().extension() == ".yaml") names.insert(entry.path().stem().string());
    }
  }
  return {names.begin(), names.end()};
}

fs::path ParseVehicle(const YamlNode& node, const fs::path& scenario_dir) {
  const std::string name = node.As<std::string>();
  if (const auto found = FindVehicleFile(scenario_dir, name)) return *found;
  std::string known;
  for (const std::string& n : KnownVehicles(scenario_dir)) {
    if (!known.empty()) known += ", ";
    known += n;
  }
  node.Fail("unknown vehicle '" + name + "': no such file next to the scenario or in " +
            "scenarios/vehicles/ (known vehicles: " + (known.empty() ? "none found" : known) + ")");
}

EgoSpec ParseEgo(const YamlNode& node) {
  node.ExpectOnlyKeys({"route", "from", "to", "via", "loops", "depart_pos_m", "depart_speed_mps",
                       "max_speed_mps", "car_follow_model"});
  EgoSpec ego;
  ego.source = SourceRef::Of(node);
  const bool has_route = node.Has("route");
  const bool has_from_to = node.Has("from") || node.Has("to");
  if (has_route == has_from_to) {
    node.Fail("give either 'route' (a list of edge ids) or 'from' and 'to' (routed by duarouter)");
  }
  if (has_route) {
    ego.route = GetEdgeList(node["route"]);
    if (ego.route.empty()) node["route"].Fail("the route needs at least one edge");
    if (node.Has("via")) node["via"].Fail("'via' goes with 'from'/'to', not with 'route'");
  } else {
    ego.from = GetEdge(node["from"]);
    ego.to = GetEdge(node["to"]);
    if (const auto via = node.Find("via")) ego.via = GetEdgeList(*via);
  }
  if (const auto loops = node.Find("loops")) {
    ego.loops = loops->As<int>();
    ego.loops_source = SourceRef::Of(*loops);
    if (ego.loops < 1) loops->Fail("expected at least 1, got " + std::to_string(ego.loops));
  } else {
    ego.loops_source = ego.source;
  }
  ego.depart_pos_m = GetNonNegative(node, "depart_pos_m", 0.0);
  ego.depart_speed_mps = GetNonNegative(node, "depart_speed_mps", 0.0);
  if (node.Has("max_speed_mps")) ego.max_speed_mps = GetPositive(node, "max_speed_mps");
  if (const auto model = node.Find("car_follow_model")) {
    ego.car_follow_model = model->As<std::string>();
    if (ego.car_follow_model != "IDM" && ego.car_follow_model != "Krauss") {
      model->Fail("expected IDM or Krauss, got '" + ego.car_follow_model + "'");
    }
  }
  return ego;
}

FlowSpec ParseFlow(const YamlNode& node, double duration_s) {
  node.ExpectOnlyKeys({"from", "to", "via", "vehs_per_hour", "begin_s", "end_s"});
  FlowSpec flow;
  flow.from = GetEdge(node["from"]);
  flow.to = GetEdge(node["to"]);
  if (const auto via = node.Find("via")) flow.via = GetEdgeList(*via);
  flow.vehs_per_hour = GetPositive(node, "vehs_per_hour");
  flow.begin_s = GetNonNegative(node, "begin_s", 0.0);
  flow.end_s = node.Has("end_s") ? GetPositive(node, "end_s") : duration_s;
  if (flow.end_s <= flow.begin_s) node["end_s"].Fail("must be after begin_s");
  return flow;
}

TrafficSpec ParseTraffic(const YamlNode& node, double duration_s) {
  TrafficSpec traffic;
  if (node.IsNull()) return traffic;
  node.ExpectOnlyKeys({"flows", "density"});
  if (const auto flows = node.Find("flows"); flows && !flows->IsNull()) {
    flows->ExpectSequence();
    for (std::size_t i = 0; i < flows->size(); ++i) {
      traffic.flows.push_back(ParseFlow(flows->At(i), duration_s));
    }
  }
  if (const auto density = node.Find("density")) {
    traffic.density = density->As<int>();
    if (traffic.density < 0) density->Fail("expected a non-negative number of vehicles");
  }
  return traffic;
}

SumoSpec ParseSumo(const YamlNode& node) {
  SumoSpec sumo;
  if (node.IsNull()) return sumo;
  node.ExpectOnlyKeys({"step_s"});
  if (node.Has("step_s")) {
    sumo.step_s = GetPositive(node, "step_s");
    if (sumo.step_s > 0.1 + 1e-12) node["step_s"].Fail("SUMO step must be at most 0.1 s");
  }
  return sumo;
}

}  // namespace

std::optional<fs::path> FindVehicleFile(const fs::path& scenario_dir_in, const std::string& name) {
  if (name.empty()) return std::nullopt;
  const fs::path scenario_dir = scenario_dir_in.empty() ? fs::path(".") : scenario_dir_in;
  fs::path file(name);
  if (!file.has_extension()) file += ".yaml";
  std::vector<fs::path> candidates = {file.is_absolute() ? file : scenario_dir / file};
  if (!file.is_absolute()) {
    for (fs::path dir = fs::absolute(scenario_dir); !dir.empty(); dir = dir.parent_path()) {
      candidates.push_back(dir / "vehicles" / file);
      candidates.push_back(dir / "scenarios" / "vehicles" / file);
      if (dir == dir.parent_path()) break;
    }
    for (const fs::path& dir : FallbackVehicleDirs()) candidates.push_back(dir / file);
  }
  std::error_code ec;
  for (const fs::path& candidate : candidates) {
    if (fs::is_regular_file(candidate, ec)) return fs::absolute(candidate).lexically_normal();
  }
  return std::nullopt;
}

Scenario LoadScenario(const fs::path& path) {
  const YamlNode root = YamlNode::LoadFile(path);
  root.ExpectOnlyKeys({"name", "seed", "duration_s", "origin", "vehicle", "network", "ego",
                       "traffic", "sumo", "sensors", "faults"});
  Scenario scenario;
  scenario.file = path;
  scenario.name = root.Get<std::string>("name");
  scenario.seed = root.Get<std::uint64_t>("seed");
  scenario.duration_s = GetPositive(root, "duration_s");
  scenario.origin = ParseOrigin(root["origin"]);
  scenario.vehicle_file = ParseVehicle(root["vehicle"], root.Directory());
  scenario.network = ParseNetwork(root["network"]);
  scenario.ego = ParseEgo(root["ego"]);
  if (const auto traffic = root.Find("traffic")) {
    scenario.traffic = ParseTraffic(*traffic, scenario.duration_s);
  }
  if (const auto sumo = root.Find("sumo")) scenario.sumo = ParseSumo(*sumo);
  if (const auto sensors = root.Find("sensors"); sensors && !sensors->IsNull()) {
    scenario.sensors = *sensors;
  }
  if (const auto faults = root.Find("faults"); faults && !faults->IsNull()) {
    scenario.faults = *faults;
  }
  return scenario;
}

}  // namespace statebench::sim
