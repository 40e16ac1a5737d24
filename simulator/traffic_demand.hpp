// Traffic demand: the vehicle types traffic is drawn from and the trips of the scenario's flows.
// Every random draw comes from a core/random.hpp stream of the scenario seed, so the same seed
// gives the same trips on every platform, and another seed other trips.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "simulator/scenario.hpp"

namespace statebench::sim {

// A SUMO vType for traffic, with the box the lidar world sees.
struct TrafficVehicleType {
  std::string id;
  double probability = 0.0;  // share of the traffic
  double length_m = 0.0;
  double width_m = 0.0;
  double height_m = 0.0;
  double max_speed_mps = 0.0;
  double accel_mps2 = 0.0;
  double decel_mps2 = 0.0;
};

// Car 80 %, van 15 %, bus 5 % (Krauss model, driver imperfection sigma 0.5).
const std::vector<TrafficVehicleType>& TrafficVehicleTypes();
const TrafficVehicleType& PickTrafficType(std::mt19937_64& rng);

struct Trip {
  std::string id;
  std::string type_id;
  double depart_s = 0.0;
  std::string from;
  std::string to;
  std::vector<std::string> via;
};

// Poisson departures (exponential gaps of mean 3600 / vehs_per_hour) of every flow within
// [begin_s, min(end_s, duration_s)), sorted by departure time. Ids "flow<i>.<k>".
std::vector<Trip> FlowTrips(const TrafficSpec& traffic, std::uint64_t seed, double duration_s);

}  // namespace statebench::sim
