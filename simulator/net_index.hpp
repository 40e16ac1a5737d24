// What the network builder needs to know about a built .net.xml before SUMO loads it: which
// normal edges exist, which edge pairs are connected, and SUMO's network offset.
#pragma once

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <utility>

#include "core/eigen_types.hpp"

namespace statebench::sim {

struct NetIndex {
  std::set<std::string> edges;  // normal edges (no internal, crossing or walking-area edges)
  std::map<std::string, double> edge_length_m;  // length of each normal edge's first lane
  std::set<std::pair<std::string, std::string>> connections;  // (from edge, to edge)
  // <location netOffset>: added by SUMO to the input coordinates. Network coordinates are used
  // as ENU directly; netconvert runs with normalisation disabled so this is zero for XML nets.
  Vec2 net_offset = Vec2::Zero();

  bool HasEdge(const std::string& id) const { return edges.count(id) > 0; }
  bool Connected(const std::string& from, const std::string& to) const {
    return connections.count({from, to}) > 0;
  }
};

// Throws std::runtime_error when the file cannot be read or parsed.
NetIndex ReadNetIndex(const std::filesystem::path& net_file);

}  // namespace statebench::sim
