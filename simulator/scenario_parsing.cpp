#include "simulator/scenario_parsing.hpp"

#include <sstream>

namespace statebench::sim {
namespace {

std::string Format(double value) {
  std::ostringstream os;
  os << value;
  return os.str();
}

}  // namespace

double GetPositive(const YamlNode& map, const std::string& key) {
  const YamlNode node = map[key];
  const double value = node.As<double>();
  if (!(value > 0.0)) node.Fail("expected a positive number, got " + Format(value));
  return value;
}

double GetPositive(const YamlNode& map, const std::string& key, double fallback) {
  return map.Has(key) ? GetPositive(map, key) : fallback;
}

double GetNonNegative(const YamlNode& map, const std::string& key, double fallback) {
  if (!map.Has(key)) return fallback;
  const YamlNode node = map[key];
  const double value = node.As<double>();
  if (value < 0.0) node.Fail("expected a non-negative number, got " + Format(value));
  return value;
}

double GetInRange(const YamlNode& map, const std::string& key, double lo, double hi) {
  const YamlNode node = map[key];
  const double value = node.As<double>();
  if (value < lo || value > hi) {
    node.Fail("expected a value in [" + Format(lo) + ", " + Format(hi) + "], got " + Format(value));
  }
  return value;
}

int GetPositiveInt(const YamlNode& map, const std::string& key, int fallback) {
  if (!map.Has(key)) return fallback;
  const YamlNode node = map[key];
  const int value = node.As<int>();
  if (value < 1) node.Fail("expected a positive integer, got " + std::to_string(value));
  return value;
}

RouteEdge GetEdge(const YamlNode& node) {
  RouteEdge edge{node.As<std::string>(), SourceRef::Of(node)};
  if (edge.edge_id.empty()) node.Fail("expected an edge id, got an empty string");
  return edge;
}

std::vector<RouteEdge> GetEdgeList(const YamlNode& node) {
  node.ExpectSequence();
  std::vector<RouteEdge> edges;
  for (std::size_t i = 0; i < node.size(); ++i) edges.push_back(GetEdge(node.At(i)));
  return edges;
}

}  // namespace statebench::sim
