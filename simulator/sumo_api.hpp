// The part of libsumo the simulator calls, behind an interface that a small module
// (simulator/sumo/libsumo_api.cpp, built as libstatebench_sumo.so) implements and that is loaded
// with dlopen the first time a simulation needs SUMO.
//
// Why not link libsumocpp directly: Debian's libsumocpp pulls in 222 shared libraries (GDAL,
// FFmpeg, OpenSceneGraph, FOX, ...) whose loading and relocation cost every `statebench`
// process about 0.35 CPU s at start-up, SUMO or not (`statebench estimate`, `results`,
// `report`, a run whose SUMO result comes from the cache). Only a process that runs SUMO now
// pays it, once.
//
// The calls mirror libsumo's (libsumo/Simulation.h, Vehicle.h, Lane.h, ...) one for one, with
// plain types; they throw what libsumo throws (libsumo::TraCIException, a std::runtime_error).
// libsumo holds one simulation per process: the caller serialises runs (sumo_run.cpp).
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace statebench::sim {

using SumoPosition = std::array<double, 3>;  // x, y, z (network coordinates, m)

struct SumoLaneLink {
  std::string approached_lane;
  std::string approached_internal;  // empty when the link enters no internal junction lane
};

struct SumoNextTls {
  char state = ' ';  // the signal for the vehicle's link: r y g G ...
  double distance_m = 0.0;
};

class SumoApi {
 public:
  virtual ~SumoApi() = default;

  // Simulation
  virtual void Load(const std::vector<std::string>& arguments) = 0;
  virtual void Close() = 0;
  virtual void Step() = 0;
  virtual std::vector<std::string> ArrivedIds() = 0;
  virtual std::vector<std::string> DepartedIds() = 0;
  virtual std::vector<std::string> StartingTeleportIds() = 0;
  // The edges of the fastest route (empty when none).
  virtual std::vector<std::string> FindRoute(const std::string& from_edge,
                                             const std::string& to_edge,
                                             const std::string& vehicle_type) = 0;
  virtual void AddRoute(const std::string& id, const std::vector<std::string>& edges) = 0;

  // Network
  virtual std::vector<std::string> LaneIds() = 0;
  virtual std::string LaneEdge(const std::string& lane) = 0;
  virtual double LaneWidth(const std::string& lane) = 0;
  virtual double LaneLength(const std::string& lane) = 0;
  virtual std::vector<SumoPosition> LaneShape(const std::string& lane) = 0;
  virtual std::vector<SumoLaneLink> LaneLinks(const std::string& lane) = 0;
  virtual std::vector<std::string> JunctionIds() = 0;
  virtual std::vector<SumoPosition> JunctionShape(const std::string& junction) = 0;

  // Vehicles
  virtual std::vector<std::string> VehicleIds() = 0;
  virtual void AddVehicle(const std::string& id, const std::string& route,
                          const std::string& type, const std::string& depart,
                          const std::string& depart_lane, const std::string& depart_pos,
                          const std::string& depart_speed) = 0;
  virtual std::string VehicleLane(const std::string& vehicle) = 0;
  virtual double VehicleLanePosition(const std::string& vehicle) = 0;
  virtual double VehicleSpeed(const std::string& vehicle) = 0;
  virtual double VehicleAcceleration(const std::string& vehicle) = 0;
  virtual SumoPosition VehiclePosition3D(const std::string& vehicle) = 0;
  virtual double VehicleAngle(const std::string& vehicle) = 0;  // deg clockwise from north
  virtual double VehicleSlope(const std::string& vehicle) = 0;  // deg
  virtual std::vector<SumoNextTls> VehicleNextTls(const std::string& vehicle) = 0;
  // The leader's id (empty when none within `distance_m`) and the gap to it.
  virtual std::pair<std::string, double> VehicleLeader(const std::string& vehicle,
                                                       double distance_m) = 0;
  virtual std::string VehicleType(const std::string& vehicle) = 0;
  virtual void SetLaneChangeMode(const std::string& vehicle, int mode) = 0;
  virtual void SetSpeed(const std::string& vehicle, double speed_mps) = 0;

  // Vehicle types
  virtual double TypeLength(const std::string& type) = 0;
  virtual double TypeWidth(const std::string& type) = 0;
  virtual double TypeHeight(const std::string& type) = 0;
};

// The module's libsumo, loaded on the first call (thread-safe). The module is looked up as
// $STATEBENCH_SUMO_MODULE when set, else libstatebench_sumo.so in ../lib beside the running
// program, else where the build put it. std::runtime_error naming every place tried and the
// loader's message when it cannot be loaded. Loading libsumo sets std::cout and std::cerr to
// fixed notation with 2 digits (its static initialisation): RunSumo, the only caller, keeps the
// streams' formatting around its first call.
SumoApi& Sumo();

}  // namespace statebench::sim

// The module's entry point: its one SumoApi instance.
extern "C" statebench::sim::SumoApi* statebench_sumo_api();
