// The SUMO routes file of a scenario: vehicle types, the ego's route and vehicle, and the flow
// trips (SUMO routes each trip between its edges when it departs).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "simulator/ego_vehicle_type.hpp"
#include "simulator/scenario.hpp"
#include "simulator/traffic_demand.hpp"

namespace statebench::sim {

inline const std::string kEgoId = "ego";
inline const std::string kEgoTypeId = "ego_type";

// `ego_edges` is the full route (loops already unrolled). Trips must be sorted by departure.
void WriteRoutesFile(const std::filesystem::path& file, const EgoSpec& ego,
                     const EgoVehicleType& type, const std::vector<std::string>& ego_edges,
                     const std::vector<Trip>& trips);

// Shortest decimal text that reads back to the same double (locale independent).
std::string FormatNumber(double value);

}  // namespace statebench::sim
