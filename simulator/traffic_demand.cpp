#include "simulator/traffic_demand.hpp"

#include <algorithm>
#include <cmath>

#include "core/random.hpp"

namespace statebench::sim {

const std::vector<TrafficVehicleType>& TrafficVehicleTypes() {
  static const std::vector<TrafficVehicleType> kTypes = {
      {"traffic_car", 0.80, 4.5, 1.8, 1.5, 50.0, 2.6, 4.5},
      {"traffic_van", 0.15, 5.5, 2.0, 2.3, 40.0, 2.0, 4.0},
      {"traffic_bus", 0.05, 12.0, 2.55, 3.2, 25.0, 1.2, 4.0},
  };
  return kTypes;
}

const TrafficVehicleType& PickTrafficType(std::mt19937_64& rng) {
  const auto& types = TrafficVehicleTypes();
  double u = Uniform01(rng);
  for (const TrafficVehicleType& type : types) {
    if (u < type.probability) return type;
    u -= type.probability;
  }
  return types.front();
}

std::vector<Trip> FlowTrips(const TrafficSpec& traffic, std::uint64_t seed, double duration_s) {
  std::vector<Trip> trips;
  for (std::size_t i = 0; i < traffic.flows.size(); ++i) {
    const FlowSpec& flow = traffic.flows[i];
    std::mt19937_64 rng = MakeRng(seed, "sumo.flow." + std::to_string(i));
    const double mean_gap_s = 3600.0 / flow.vehs_per_hour;
    const double end_s = std::min(flow.end_s, duration_s);
    double t = flow.begin_s;
    for (int k = 0;; ++k) {
      t += -mean_gap_s * std::log1p(-Uniform01(rng));
      if (t >= end_s) break;
      Trip trip;
      trip.id = "flow" + std::to_string(i) + "." + std::to_string(k);
      trip.type_id = PickTrafficType(rng).id;
      trip.depart_s = t;
      trip.from = flow.from.edge_id;
      trip.to = flow.to.edge_id;
      for (const RouteEdge& v : flow.via) trip.via.push_back(v.edge_id);
      trips.push_back(std::move(trip));
    }
  }
  std::stable_sort(trips.begin(), trips.end(),
                   [](const Trip& a, const Trip& b) { return a.depart_s < b.depart_s; });
  return trips;
}

}  // namespace statebench::sim
