// Builds what SUMO loads for a scenario, in a working directory (usually <run out dir>/sumo):
// the network (netgenerate from parameters, or netconvert from plain XML), the ego route
// (explicit, or routed by duarouter), and the routes file with the ego and the flow trips.
// Every tool runs as a subprocess with its output in <work_dir>/<tool>.log; a failure or a
// missing tool is an InputError naming the scenario field it serves.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "simulator/ego_vehicle_type.hpp"
#include "simulator/net_index.hpp"
#include "simulator/scenario.hpp"
#include "simulator/sumo_tools.hpp"

namespace statebench::sim {

struct BuiltNetwork {
  std::filesystem::path work_dir;
  std::filesystem::path net_file;      // <work_dir>/net.net.xml
  std::filesystem::path routes_file;   // <work_dir>/routes.rou.xml
  std::vector<std::string> ego_route;  // edge ids, loops unrolled
  NetIndex index;
};

class NetworkBuilder {
 public:
  explicit NetworkBuilder(SumoTools tools = SumoTools::Find()) : tools_(std::move(tools)) {}

  // Deterministic: the same scenario gives the same files (the network does not depend on the
  // scenario seed; the flow trips do). Throws InputError on bad input or a failing tool.
  BuiltNetwork Build(const Scenario& scenario, const EgoVehicleType& ego_type,
                     const std::filesystem::path& work_dir) const;

 private:
  std::filesystem::path BuildNet(const NetworkSpec& spec,
                                 const std::filesystem::path& work_dir) const;
  std::vector<std::string> EgoRoute(const EgoSpec& ego, const NetIndex& index,
                                    const std::filesystem::path& net_file,
                                    const std::filesystem::path& work_dir) const;

  SumoTools tools_;
};

// The netgenerate arguments for a generated network (without the output file).
std::vector<std::string> NetgenerateArguments(const GeneratedNetwork& net);

}  // namespace statebench::sim
