// The `network` section of a scenario file.
#include <string>

#include "simulator/scenario_parsing.hpp"

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;

GridNetwork ParseGrid(const YamlNode& node) {
  if (node.IsNull()) return {};
  node.ExpectOnlyKeys({"number", "x_number", "y_number", "length_m", "x_length_m", "y_length_m",
                       "attach_length_m"});
  GridNetwork grid;
  const int number = GetPositiveInt(node, "number", grid.x_number);
  const double length_m = GetPositive(node, "length_m", grid.x_length_m);
  grid.x_number = GetPositiveInt(node, "x_number", number);
  grid.y_number = GetPositiveInt(node, "y_number", number);
  grid.x_length_m = GetPositive(node, "x_length_m", length_m);
  grid.y_length_m = GetPositive(node, "y_length_m", length_m);
  grid.attach_length_m = GetNonNegative(node, "attach_length_m", 0.0);
  if (grid.x_number < 2 && grid.y_number < 2) node.Fail("a grid needs at least 2 junctions");
  return grid;
}

SpiderNetwork ParseSpider(const YamlNode& node) {
  if (node.IsNull()) return {};
  node.ExpectOnlyKeys({"arm_number", "circle_number", "space_radius_m", "omit_center"});
  SpiderNetwork spider;
  spider.arm_number = GetPositiveInt(node, "arm_number", spider.arm_number);
  spider.circle_number = GetPositiveInt(node, "circle_number", spider.circle_number);
  spider.space_radius_m = GetPositive(node, "space_radius_m", spider.space_radius_m);
  spider.omit_center = node.Get<bool>("omit_center", false);
  if (spider.arm_number < 3) node["arm_number"].Fail("a spider network needs at least 3 arms");
  return spider;
}

RandomNetwork ParseRandom(const YamlNode& node) {
  if (node.IsNull()) return {};
  node.ExpectOnlyKeys({"iterations", "min_distance_m", "max_distance_m", "bidi_probability"});
  RandomNetwork random;
  random.iterations = GetPositiveInt(node, "iterations", random.iterations);
  random.min_distance_m = GetPositive(node, "min_distance_m", random.min_distance_m);
  random.max_distance_m = GetPositive(node, "max_distance_m", random.max_distance_m);
  if (node.Has("bidi_probability")) {
    random.bidi_probability = GetInRange(node, "bidi_probability", 0.0, 1.0);
  }
  if (random.max_distance_m < random.min_distance_m) {
    node["max_distance_m"].Fail("must not be below min_distance_m");
  }
  return random;
}

GeneratedNetwork ParseGenerate(const YamlNode& node) {
  node.ExpectOnlyKeys({"grid", "spider", "random", "lanes", "lane_width_m", "speed_mps",
                       "traffic_lights", "tls_cycle_s", "elevation", "seed"});
  GeneratedNetwork net;
  const int kinds = int{node.Has("grid")} + int{node.Has("spider")} + int{node.Has("random")};
  if (kinds != 1) node.Fail("give exactly one of 'grid', 'spider' or 'random'");
  if (node.Has("grid")) {
    net.kind = GeneratedNetwork::Kind::kGrid;
    net.grid = ParseGrid(node["grid"]);
  } else if (node.Has("spider")) {
    net.kind = GeneratedNetwork::Kind::kSpider;
    net.spider = ParseSpider(node["spider"]);
  } else {
    net.kind = GeneratedNetwork::Kind::kRandom;
    net.random = ParseRandom(node["random"]);
  }
  net.lanes = GetPositiveInt(node, "lanes", net.lanes);
  net.lane_width_m = GetPositive(node, "lane_width_m", net.lane_width_m);
  net.speed_mps = GetPositive(node, "speed_mps", net.speed_mps);
  net.traffic_lights = node.Get<bool>("traffic_lights", false);
  net.tls_cycle_s = node.Has("tls_cycle_s") ? GetPositiveInt(node, "tls_cycle_s", 0) : 0;
  if (const auto elevation = node.Find("elevation"); elevation && !elevation->IsNull()) {
    elevation->ExpectOnlyKeys({"sigma_m", "limit_m"});
    net.elevation_sigma_m = GetPositive(*elevation, "sigma_m");
    net.elevation_limit_m = GetPositive(*elevation, "limit_m", 2.0 * net.elevation_sigma_m);
  }
  net.seed = node.Get<std::uint64_t>("seed", net.seed);
  return net;
}

fs::path ExistingFile(const YamlNode& node) {
  const std::string name = node.As<std::string>();
  const fs::path path = node.ResolvePath(name);
  std::error_code ec;
  if (name.empty() || !fs::is_regular_file(path, ec)) {
    node.Fail("file not found: " + path.string());
  }
  return path;
}

XmlNetwork ParseXml(const YamlNode& node) {
  XmlNetwork xml;
  xml.nodes = ExistingFile(node["nodes"]);
  xml.edges = ExistingFile(node["edges"]);
  if (const auto connections = node.Find("connections")) {
    xml.connections = ExistingFile(*connections);
  }
  if (const auto tls = node.Find("traffic_lights")) xml.traffic_lights = ExistingFile(*tls);
  return xml;
}

}  // namespace

NetworkSpec ParseNetwork(const YamlNode& node) {
  node.ExpectOnlyKeys({"generate", "nodes", "edges", "connections", "traffic_lights"});
  NetworkSpec spec;
  spec.source = SourceRef::Of(node);
  const bool has_xml = node.Has("nodes") || node.Has("edges");
  if (node.Has("generate") == has_xml) {
    node.Fail("give either 'generate' (netgenerate parameters) or 'nodes' and 'edges' " +
              std::string("(plain XML built with netconvert)"));
  }
  if (node.Has("generate")) {
    if (node.Has("connections") || node.Has("traffic_lights")) {
      node.Fail("'connections' and 'traffic_lights' go with 'nodes'/'edges'");
    }
    spec.generate = ParseGenerate(node["generate"]);
  } else {
    spec.xml = ParseXml(node);
  }
  return spec;
}

}  // namespace statebench::sim
