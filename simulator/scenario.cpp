#include "simulator/scenario.hpp"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>

#include "core/yaml_merge.hpp"
#include "estimator/estimator_factory.hpp"
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
                       "parked_s", "max_speed_mps", "car_follow_model"});
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
  ego.parked_s = GetNonNegative(node, "parked_s", 0.0);
  if (ego.parked_s > 0.0 && ego.depart_speed_mps > 0.0) {
    node["parked_s"].Fail("a parked start departs at 0 m/s: set depart_speed_mps to 0");
  }
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

// A label names an output folder: letters, digits, '_', '-', '.', not starting with '.'.
bool IsValidLabel(const std::string& label) {
  if (label.empty() || label.front() == '.') return false;
  return std::all_of(label.begin(), label.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '.';
  });
}

std::string KnownEstimatorList() {
  std::string list;
  for (const std::string& k : est::KnownEstimators()) list += (list.empty() ? "" : ", ") + k;
  return list;
}

// One entry: `- ekf` (type, labelled by it) or `- {name, type, config, overrides, inputs}`.
EstimatorSpec ParseEstimatorEntry(const YamlNode& entry, const fs::path& scenario_dir) {
  EstimatorSpec spec;
  spec.source = SourceRef::Of(entry);
  const YamlNode type_node = entry.IsScalar() ? entry : entry["type"];
  if (!entry.IsScalar()) entry.ExpectOnlyKeys({"name", "type", "config", "overrides", "inputs"});
  spec.type = type_node.As<std::string>();
  const std::vector<std::string> known = est::KnownEstimators();
  if (std::find(known.begin(), known.end(), spec.type) == known.end()) {
    type_node.Fail("unknown estimator type '" + spec.type + "' (known: " + KnownEstimatorList() +
                   ")");
  }
  spec.label = spec.type;
  if (const auto name = entry.IsScalar() ? std::nullopt : entry.Find("name")) {
    spec.label = name->As<std::string>();
    if (!IsValidLabel(spec.label)) {
      name->Fail("'" + spec.label +
                 "' cannot name an output folder: use letters, digits, '_', "
                 "'-' and '.' (not first)");
    }
  }
  if (const auto config = entry.IsScalar() ? std::nullopt : entry.Find("config")) {
    spec.config = config->ResolvePath(config->As<std::string>());
    std::error_code ec;
    if (!fs::is_regular_file(spec.config, ec)) {
      config->Fail("no such estimator options file: " + spec.config.string());
    }
    spec.config = fs::absolute(spec.config).lexically_normal();
  } else if (const auto found = FindEstimatorConfigFile(scenario_dir, spec.type)) {
    spec.config = *found;
  }
  if (const auto inputs = entry.IsScalar() ? std::nullopt : entry.Find("inputs")) {
    inputs->ExpectSequence();
    if (inputs->size() == 0)
      inputs->Fail("empty list: name the sensors, or leave 'inputs' out for all");
    for (std::size_t i = 0; i < inputs->size(); ++i) {
      const std::string id = inputs->At(i).As<std::string>();
      if (std::find(spec.inputs.begin(), spec.inputs.end(), id) != spec.inputs.end()) {
        inputs->At(i).Fail("sensor '" + id + "' named twice");
      }
      spec.inputs.push_back(id);
    }
  }
  if (const auto overrides = entry.IsScalar() ? std::nullopt : entry.Find("overrides")) {
    if (!overrides->IsNull()) {
      if (!overrides->IsMap()) {
        overrides->Fail("expected a map of option overrides, e.g. {window_s: 0.5}");
      }
      spec.overrides = *overrides;
    }
  }
  return spec;
}

std::vector<EstimatorSpec> ParseEstimators(const YamlNode& node, const fs::path& scenario_dir) {
  node.ExpectSequence();
  if (node.size() == 0) {
    node.Fail(
        "empty list: name at least one estimator, or leave 'estimators' out for the "
        "default (factor_graph and ekf)");
  }
  std::vector<EstimatorSpec> specs;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YamlNode entry = node.At(i);
    EstimatorSpec spec = ParseEstimatorEntry(entry, scenario_dir);
    for (const EstimatorSpec& other : specs) {
      if (other.label != spec.label) continue;
      const YamlNode at = entry.IsMap() && entry.Has("name") ? entry["name"] : entry;
      at.Fail("duplicate estimator name '" + spec.label + "' (also " + other.source.field + " at " +
              other.source.where + "): give each entry its own 'name'");
    }
    specs.push_back(std::move(spec));
  }
  return specs;
}

}  // namespace

std::optional<fs::path> FindEstimatorConfigFile(const fs::path& scenario_dir_in,
                                                const std::string& type) {
  if (type.empty()) return std::nullopt;
  const fs::path scenario_dir = scenario_dir_in.empty() ? fs::path(".") : scenario_dir_in;
  const fs::path file = type + ".yaml";
  std::vector<fs::path> candidates;
  for (fs::path dir = fs::absolute(scenario_dir); !dir.empty(); dir = dir.parent_path()) {
    candidates.push_back(dir / "estimators" / file);
    candidates.push_back(dir / "scenarios" / "estimators" / file);
    if (dir == dir.parent_path()) break;
  }
  if (const char* source_dir = std::getenv("STATEBENCH_SOURCE_DIR")) {
    candidates.push_back(fs::path(source_dir) / "scenarios" / "estimators" / file);
  }
  std::error_code ec;
  const fs::path cwd = fs::current_path(ec);
  if (!ec) candidates.push_back(cwd / "scenarios" / "estimators" / file);
  for (const fs::path& candidate : candidates) {
    if (fs::is_regular_file(candidate, ec)) return fs::absolute(candidate).lexically_normal();
  }
  return std::nullopt;
}

std::vector<EstimatorSpec> ScenarioEstimators(const Scenario& scenario) {
  if (!scenario.estimators.empty()) return scenario.estimators;
  std::vector<EstimatorSpec> specs;
  for (const std::string type : {"factor_graph", "ekf"}) {
    EstimatorSpec spec;
    spec.label = type;
    spec.type = type;
    spec.config = FindEstimatorConfigFile(scenario.file.parent_path(), type).value_or(fs::path());
    spec.source = {scenario.file.string(), "estimators"};
    specs.push_back(std::move(spec));
  }
  return specs;
}

std::string EstimatorConfigText(const EstimatorSpec& spec, const Scenario& scenario) {
  const YAML::Node base =
      spec.config.empty() ? YAML::Node(YAML::NodeType::Map) : YamlNode::LoadFile(spec.config).raw();
  const YAML::Node merged = MergeYaml(base, spec.overrides ? spec.overrides->raw() : YAML::Node());
  std::string text = "# Options of estimator '" + spec.label + "' (" + spec.type +
                     ") of scenario " + scenario.file.string() + " (" + spec.source.where +
                     "):\n# " + (spec.config.empty() ? "built-in defaults" : spec.config.string());
  text += spec.overrides ? ", with the scenario's overrides merged over it.\n" : ".\n";
  const std::string body = ToYamlText(merged);
  return text + (body.empty() ? "{}\n" : body);
}

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
                       "traffic", "sumo", "sensors", "faults", "mismatch", "estimators"});
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
  if (const auto mismatch = root.Find("mismatch"); mismatch && !mismatch->IsNull()) {
    scenario.mismatch = ParseMismatch(*mismatch);
  }
  if (const auto estimators = root.Find("estimators"); estimators && !estimators->IsNull()) {
    scenario.estimators = ParseEstimators(*estimators, root.Directory());
  }
  return scenario;
}

}  // namespace statebench::sim
