#include "simulator/scenario_resolution.hpp"

#include <cctype>
#include <stdexcept>

#include "core/content_hash.hpp"
#include "core/error.hpp"
#include "core/yaml_merge.hpp"
#include "core/yaml_node.hpp"
#include "simulator/scenario.hpp"
#include "simulator/scenario_sensors.hpp"

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;

constexpr const char* kNetworkFiles[] = {"nodes", "edges", "connections", "traffic_lights"};

struct Segment {
  std::string key;
  std::vector<std::size_t> indices;  // key[i][j]
};

std::vector<Segment> SplitPath(const std::string& path) {
  if (path.empty()) throw std::invalid_argument("empty path");
  std::vector<Segment> segments;
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t dot = path.find('.', start);
    const std::string part = path.substr(start, dot == std::string::npos ? dot : dot - start);
    Segment segment;
    const std::size_t bracket = part.find('[');
    segment.key = part.substr(0, bracket);
    if (segment.key.empty()) {
      throw std::invalid_argument("path '" + path + "': empty key");
    }
    for (std::size_t pos = bracket; pos != std::string::npos && pos < part.size();) {
      const std::size_t close = part.find(']', pos);
      const std::string digits =
          close == std::string::npos ? "" : part.substr(pos + 1, close - pos - 1);
      if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) {
        throw std::invalid_argument("path '" + path + "': expected [index] in '" + part + "'");
      }
      segment.indices.push_back(std::stoul(digits));
      pos = close + 1;
      if (pos < part.size() && part[pos] != '[') {
        throw std::invalid_argument("path '" + path + "': unexpected text after ']' in '" + part +
                                    "'");
      }
    }
    segments.push_back(std::move(segment));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return segments;
}

std::string Keys(const YAML::Node& map) {
  std::string keys;
  if (!map.IsMap()) return keys;
  for (const auto& entry : map) keys += (keys.empty() ? "" : ", ") + entry.first.as<std::string>();
  return keys;
}

// The element of a list of maps whose `field` equals `id`, or an undefined node.
YAML::Node ElementById(const YAML::Node& list, const std::string& field, const std::string& id) {
  if (!list.IsSequence()) return YAML::Node(YAML::NodeType::Undefined);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node element = list[i];
    if (element.IsMap() && element[field] && element[field].IsScalar() &&
        element[field].as<std::string>() == id) {
      return element;
    }
  }
  return YAML::Node(YAML::NodeType::Undefined);
}

std::string Ids(const YAML::Node& list, const std::string& field) {
  std::string ids;
  if (!list.IsSequence()) return ids;
  for (const auto& element : list) {
    if (element.IsMap() && element[field]) {
      ids += (ids.empty() ? "" : ", ") + element[field].as<std::string>();
    }
  }
  return ids;
}

// Walks the path. Returns the parent map of the last key, throwing when an intermediate segment
// does not exist; with `create_option_maps`, a missing map segment inside an estimator's options
// is created instead (the estimator's option table, not the options file, says which sections
// exist: a file need not list the sections it leaves at their defaults).
struct Walk {
  YAML::Node parent;     // map holding the last key
  std::string last_key;  // the last segment's key
  std::vector<std::size_t> last_indices;
};

Walk WalkPath(const YAML::Node& root, const std::string& path, bool create_option_maps = false) {
  const std::vector<Segment> segments = SplitPath(path);
  YAML::Node node;
  node.reset(root);
  std::string walked;
  bool in_estimator_options = false;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const Segment& segment = segments[s];
    const bool last = s + 1 == segments.size();
    const std::string here = walked.empty() ? "the scenario" : "'" + walked + "'";
    // Named list elements: a sensor by id, an estimator by label.
    if (s == 1 && segment.indices.empty() && !last && segments[0].indices.empty() &&
        (segments[0].key == "sensors" || segments[0].key == "estimators")) {
      const bool sensors = segments[0].key == "sensors";
      const YAML::Node list = sensors ? node["sensors"] : node;
      const YAML::Node element = ElementById(list, sensors ? "id" : "name", segment.key);
      if (element) {
        node.reset(sensors ? element : element["overrides"]);
        walked += "." + segment.key;
        in_estimator_options = !sensors;
        continue;
      }
      if (!sensors) {
        throw std::invalid_argument("no estimator '" + segment.key + "' in the scenario (" +
                                    "estimators: " + Ids(node, "name") + ")");
      }
    }
    if (!node.IsMap()) {
      throw std::invalid_argument(here + " is not a map: no field '" + segment.key + "' in it");
    }
    if (last && segment.indices.empty()) return {node, segment.key, {}};
    YAML::Node child = node[segment.key];
    if (!child && create_option_maps && in_estimator_options && segment.indices.empty()) {
      node[segment.key] = YAML::Node(YAML::NodeType::Map);
      child.reset(node[segment.key]);
    }
    if (!child) {
      std::string known = Keys(node);
      if (walked == "sensors") known += "; sensor ids: " + Ids(node["sensors"], "id");
      throw std::invalid_argument("no field '" + segment.key + "' in " + here + " (fields: " +
                                  known + ")");
    }
    walked += (walked.empty() ? "" : ".") + segment.key;
    node.reset(child);
    for (std::size_t k = 0; k < segment.indices.size(); ++k) {
      const std::size_t index = segment.indices[k];
      if (!node.IsSequence() || index >= node.size()) {
        throw std::invalid_argument(
            "'" + walked + "' " +
            (node.IsSequence() ? "has " + std::to_string(node.size()) + " elements, no [" +
                                     std::to_string(index) + "]"
                               : "is not a list"));
      }
      if (last && k + 1 == segment.indices.size()) {
        Walk walk;
        walk.parent.reset(node);
        walk.last_indices = {index};
        return walk;
      }
      YAML::Node element = node[index];
      node.reset(element);
      walked += '[';
      walked += std::to_string(index);
      walked += ']';
    }
  }
  throw std::invalid_argument("path '" + path + "' names no value");
}

void Require(const YamlNode& node, const std::string& what) {
  if (node.IsNull()) node.Fail("missing " + what);
}

YAML::Node ResolvedSensors(const Scenario& scenario) {
  Require(*scenario.sensors, "sensor setup");
  const ScenarioSensors sensors = LoadScenarioSensors(scenario);  // checks setup and faults
  const YamlNode& node = *scenario.sensors;
  if (!node.IsScalar()) return YAML::Clone(node.raw());
  const auto file = FindSensorSetupFile(scenario.file, node.As<std::string>());
  return YAML::Clone(YamlNode::LoadFile(*file).raw());
}

}  // namespace

YAML::Node ResolveScenario(const fs::path& scenario_file) {
  const Scenario scenario = LoadScenario(scenario_file);
  YAML::Node root = YAML::Clone(YamlNode::LoadFile(scenario_file).raw());
  root["seed"] = scenario.seed;
  root["vehicle"] = fs::absolute(scenario.vehicle_file).lexically_normal().string();
  if (scenario.network.xml) {
    const XmlNetwork& xml = *scenario.network.xml;
    YAML::Node network = root["network"];
    network["nodes"] = fs::absolute(xml.nodes).lexically_normal().string();
    network["edges"] = fs::absolute(xml.edges).lexically_normal().string();
    if (xml.connections) {
      network["connections"] = fs::absolute(*xml.connections).lexically_normal().string();
    }
    if (xml.traffic_lights) {
      network["traffic_lights"] = fs::absolute(*xml.traffic_lights).lexically_normal().string();
    }
  }
  if (scenario.sensors) root["sensors"] = ResolvedSensors(scenario);
  YAML::Node estimators(YAML::NodeType::Sequence);
  for (const EstimatorSpec& spec : ScenarioEstimators(scenario)) {
    const YAML::Node base = spec.config.empty() ? YAML::Node(YAML::NodeType::Map)
                                                : YamlNode::LoadFile(spec.config).raw();
    YAML::Node entry(YAML::NodeType::Map);
    entry["name"] = spec.label;
    entry["type"] = spec.type;
    entry["overrides"] =
        MergeYaml(base, spec.overrides ? spec.overrides->raw() : YAML::Node());
    if (!entry["overrides"].IsMap()) entry["overrides"] = YAML::Node(YAML::NodeType::Map);
    if (!spec.inputs.empty()) {
      YAML::Node inputs(YAML::NodeType::Sequence);
      for (const std::string& id : spec.inputs) inputs.push_back(id);
      entry["inputs"] = inputs;
    }
    estimators.push_back(entry);
  }
  root["estimators"] = estimators;
  return root;
}

void SetScenarioValue(YAML::Node& resolved, const std::string& path, const YAML::Node& value) {
  Walk walk = WalkPath(resolved, path, /*create_option_maps=*/true);
  if (!walk.last_indices.empty()) {
    walk.parent[walk.last_indices.front()] = YAML::Clone(value);
  } else {
    walk.parent[walk.last_key] = YAML::Clone(value);
  }
}

YAML::Node ScenarioValue(const YAML::Node& resolved, const std::string& path) {
  try {
    const Walk walk = WalkPath(resolved, path);
    if (!walk.last_indices.empty()) return walk.parent[walk.last_indices.front()];
    const YAML::Node& parent = walk.parent;
    return parent[walk.last_key];
  } catch (const std::invalid_argument&) {
    return YAML::Node(YAML::NodeType::Undefined);
  }
}

std::string ScenarioFingerprint(const YAML::Node& resolved) {
  YAML::Node copy = YAML::Clone(resolved);
  const auto hash_file = [](YAML::Node node) {
    if (node && node.IsScalar()) node = "sha256:" + Sha256OfFile(node.as<std::string>());
  };
  hash_file(copy["vehicle"]);
  if (copy["network"] && copy["network"].IsMap()) {
    for (const char* key : kNetworkFiles) hash_file(copy["network"][key]);
  }
  return ToYamlText(copy);
}

}  // namespace statebench::sim
