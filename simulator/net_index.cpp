#include "simulator/net_index.hpp"

#include <cstdio>
#include <stdexcept>
#include <string>

#include "simulator/xml_scan.hpp"

namespace statebench::sim {

NetIndex ReadNetIndex(const std::filesystem::path& net_file) {
  NetIndex index;
  std::string current_edge;  // normal edge whose lanes follow, empty otherwise
  ForEachXmlElement(ReadTextFile(net_file), [&](const XmlElement& e) {
    if (e.name == "edge") {
      const bool normal = e.Attribute("function", "normal") == "normal";
      current_edge = normal ? e.Attribute("id") : "";
      if (normal) index.edges.insert(current_edge);
    } else if (e.name == "lane") {
      if (!current_edge.empty() && index.edge_length_m.count(current_edge) == 0) {
        index.edge_length_m[current_edge] = std::stod(e.Attribute("length", "0"));
      }
    } else if (e.name == "connection") {
      current_edge.clear();
      const std::string from = e.Attribute("from");
      if (!from.empty() && from.front() != ':') index.connections.insert({from, e.Attribute("to")});
    } else if (e.name == "location") {
      double x = 0.0;
      double y = 0.0;
      if (std::sscanf(e.Attribute("netOffset", "0,0").c_str(), "%lf,%lf", &x, &y) != 2) {
        throw std::runtime_error(net_file.string() + ": malformed netOffset");
      }
      index.net_offset = Vec2(x, y);
    }
  });
  if (index.edges.empty()) throw std::runtime_error(net_file.string() + ": no edges");
  return index;
}

}  // namespace statebench::sim
