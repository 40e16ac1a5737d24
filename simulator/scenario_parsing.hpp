// Field readers shared by the scenario parser's files (internal to simulator/).
#pragma once

#include <string>
#include <vector>

#include "core/yaml_node.hpp"
#include "simulator/scenario.hpp"

namespace statebench::sim {

double GetPositive(const YamlNode& map, const std::string& key);
double GetPositive(const YamlNode& map, const std::string& key, double fallback);
double GetNonNegative(const YamlNode& map, const std::string& key, double fallback);
double GetInRange(const YamlNode& map, const std::string& key, double lo, double hi);
int GetPositiveInt(const YamlNode& map, const std::string& key, int fallback);

// A SUMO edge id (non-empty string) with its location.
RouteEdge GetEdge(const YamlNode& node);
std::vector<RouteEdge> GetEdgeList(const YamlNode& node);

// The `network` section: {generate: {...}} or {nodes, edges, connections?, traffic_lights?}.
NetworkSpec ParseNetwork(const YamlNode& node);

}  // namespace statebench::sim
