// libstatebench_sumo.so: simulator/sumo_api.hpp's SumoApi on libsumo, call for call. The only
// translation unit that links libsumocpp; the simulator loads it with dlopen (sumo_api.cpp).
#include <libsumo/libsumo.h>

#include "simulator/sumo_api.hpp"

namespace statebench::sim {
namespace {

std::vector<SumoPosition> ToPositions(const libsumo::TraCIPositionVector& shape) {
  std::vector<SumoPosition> out;
  out.reserve(shape.value.size());
  for (const auto& p : shape.value) out.push_back({p.x, p.y, p.z});
  return out;
}

class Libsumo final : public SumoApi {
 public:
  void Load(const std::vector<std::string>& arguments) override {
    libsumo::Simulation::load(arguments);
  }
  void Close() override { libsumo::Simulation::close(); }
  void Step() override { libsumo::Simulation::step(); }
  std::vector<std::string> ArrivedIds() override {
    return libsumo::Simulation::getArrivedIDList();
  }
  std::vector<std::string> DepartedIds() override {
    return libsumo::Simulation::getDepartedIDList();
  }
  std::vector<std::string> StartingTeleportIds() override {
    return libsumo::Simulation::getStartingTeleportIDList();
  }
  std::vector<std::string> FindRoute(const std::string& from_edge, const std::string& to_edge,
                                     const std::string& vehicle_type) override {
    return libsumo::Simulation::findRoute(from_edge, to_edge, vehicle_type).edges;
  }
  void AddRoute(const std::string& id, const std::vector<std::string>& edges) override {
    libsumo::Route::add(id, edges);
  }

  std::vector<std::string> LaneIds() override { return libsumo::Lane::getIDList(); }
  std::string LaneEdge(const std::string& lane) override {
    return libsumo::Lane::getEdgeID(lane);
  }
  double LaneWidth(const std::string& lane) override { return libsumo::Lane::getWidth(lane); }
  double LaneLength(const std::string& lane) override { return libsumo::Lane::getLength(lane); }
  std::vector<SumoPosition> LaneShape(const std::string& lane) override {
    return ToPositions(libsumo::Lane::getShape(lane));
  }
  std::vector<SumoLaneLink> LaneLinks(const std::string& lane) override {
    std::vector<SumoLaneLink> out;
    for (const libsumo::TraCIConnection& link : libsumo::Lane::getLinks(lane)) {
      out.push_back({link.approachedLane, link.approachedInternal});
    }
    return out;
  }
  std::vector<std::string> JunctionIds() override { return libsumo::Junction::getIDList(); }
  std::vector<SumoPosition> JunctionShape(const std::string& junction) override {
    return ToPositions(libsumo::Junction::getShape(junction));
  }

  std::vector<std::string> VehicleIds() override { return libsumo::Vehicle::getIDList(); }
  void AddVehicle(const std::string& id, const std::string& route, const std::string& type,
                  const std::string& depart, const std::string& depart_lane,
                  const std::string& depart_pos, const std::string& depart_speed) override {
    libsumo::Vehicle::add(id, route, type, depart, depart_lane, depart_pos, depart_speed);
  }
  std::string VehicleLane(const std::string& vehicle) override {
    return libsumo::Vehicle::getLaneID(vehicle);
  }
  double VehicleLanePosition(const std::string& vehicle) override {
    return libsumo::Vehicle::getLanePosition(vehicle);
  }
  double VehicleSpeed(const std::string& vehicle) override {
    return libsumo::Vehicle::getSpeed(vehicle);
  }
  double VehicleAcceleration(const std::string& vehicle) override {
    return libsumo::Vehicle::getAcceleration(vehicle);
  }
  SumoPosition VehiclePosition3D(const std::string& vehicle) override {
    const libsumo::TraCIPosition p = libsumo::Vehicle::getPosition3D(vehicle);
    return {p.x, p.y, p.z};
  }
  double VehicleAngle(const std::string& vehicle) override {
    return libsumo::Vehicle::getAngle(vehicle);
  }
  double VehicleSlope(const std::string& vehicle) override {
    return libsumo::Vehicle::getSlope(vehicle);
  }
  std::vector<SumoNextTls> VehicleNextTls(const std::string& vehicle) override {
    std::vector<SumoNextTls> out;
    for (const libsumo::TraCINextTLSData& tls : libsumo::Vehicle::getNextTLS(vehicle)) {
      out.push_back({tls.state, tls.dist});
    }
    return out;
  }
  std::pair<std::string, double> VehicleLeader(const std::string& vehicle,
                                               double distance_m) override {
    return libsumo::Vehicle::getLeader(vehicle, distance_m);
  }
  std::string VehicleType(const std::string& vehicle) override {
    return libsumo::Vehicle::getTypeID(vehicle);
  }
  void SetLaneChangeMode(const std::string& vehicle, int mode) override {
    libsumo::Vehicle::setLaneChangeMode(vehicle, mode);
  }
  void SetSpeed(const std::string& vehicle, double speed_mps) override {
    libsumo::Vehicle::setSpeed(vehicle, speed_mps);
  }

  double TypeLength(const std::string& type) override {
    return libsumo::VehicleType::getLength(type);
  }
  double TypeWidth(const std::string& type) override {
    return libsumo::VehicleType::getWidth(type);
  }
  double TypeHeight(const std::string& type) override {
    return libsumo::VehicleType::getHeight(type);
  }
};

}  // namespace
}  // namespace statebench::sim

extern "C" statebench::sim::SumoApi* statebench_sumo_api() {
  static statebench::sim::Libsumo api;
  return &api;
}
