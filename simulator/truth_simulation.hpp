// The truth run loop: a scenario's SUMO run, then the ego vehicle re-driving SUMO's route and
// speed profile at 1 kHz, streamed one TruthSample at a time.
//
// Two passes. SUMO runs first over the whole scenario (sumo_run.hpp): the ego's reference
// (driven lane centre line, arc length, speed and acceleration every SUMO step) and the traffic.
// Then the vehicle model (vehicle_simulation.hpp) tracks that reference on the smoothed centre
// line over the terrain fitted to the network. Traffic therefore reacts to SUMO's ego, which the
// model follows to a few decimetres; the ego is not moved back into SUMO (moveToXY), so the
// SUMO result can be computed once and reused by every sensor seed.
//
// SUMO's arc length and speed are 3D (along the sloped lane); the vehicle model's planar states
// live in the horizontal projection, so the reference is mapped through the driven polyline's
// horizontal arc length.
#pragma once

#include "simulator/cached_stages.hpp"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/binary_io.hpp"
#include "core/truth.hpp"
#include "simulator/scenario.hpp"
#include "simulator/sumo_result.hpp"
#include "simulator/sumo_run.hpp"
#include "simulator/terrain.hpp"
#include "simulator/truth_record.hpp"
#include "simulator/vehicle_params.hpp"
#include "simulator/vehicle_simulation.hpp"

namespace statebench::sim {

// Statistics of the truth generated so far.
struct TruthSummary {
  std::string scenario;
  std::uint64_t seed = 0;
  std::string vehicle;
  double duration_s = 0.0;
  double distance_m = 0.0;
  double max_speed_mps = 0.0;
  double max_lateral_accel_mps2 = 0.0;  // |a_y| in the body frame (no gravity)
  double max_yaw_rate_radps = 0.0;
  double rms_lateral_error_m = 0.0;     // body origin to the smoothed route centre line
  double max_lateral_error_m = 0.0;
  double max_longitudinal_error_m = 0.0;  // model behind/ahead of SUMO's ego along the route
  double distance_after_60s_m = 0.0;
  int max_traffic_vehicles = 0;
  int traffic_lights_stops = 0;  // times the SUMO ego stopped with a red/yellow light ahead
  bool ego_arrived = false;
};

class TruthSimulation {
 public:
  // Builds the network, runs SUMO (files in work_dir/sumo) and sets the vehicle on its path.
  // Throws InputError on bad scenario or vehicle files, or when SUMO cannot run the route.
  // With `cache`, the SUMO result and the vehicle model's samples come from the stage cache
  // when it holds them (the same bits), and go into it when the truth runs to its end.
  TruthSimulation(const Scenario& scenario, const std::filesystem::path& work_dir,
                  const SumoRunOptions& sumo_options = {}, const StageCacheUse& cache = {});

  // The next 1 kHz truth sample (the first is t = 0); false once the end time is reached.
  bool Next(TruthSample* sample);

  TimeNs end_ns() const { return end_ns_; }
  const Scenario& scenario() const { return scenario_; }
  const VehicleParams& vehicle() const { return params_; }
  const SumoResult& sumo() const { return sumo_; }
  const Terrain& terrain() const { return *terrain_; }
  const Path& path() const { return *path_; }
  const TruthSummary& summary() const { return summary_; }

 private:
  // SUMO reference at time t_ns, mapped to the body origin and horizontal arc length.
  void Reference(TimeNs t_ns, double* s_raw_m, double* v_mps, double* a_mps2) const;
  double HorizontalArcLength(double s3d_m, double* ds2d_ds3d) const;
  // The vehicle model's next step (false past the end).
  bool Simulate(TrackedTruth* truth);
  void Accumulate(const TrackedTruth& truth);
  // The vehicle stage through the cache: replay_ when it holds the samples, record_ otherwise.
  void OpenVehicleStage(const std::optional<std::string>& truth_key, const StageCacheUse& cache);
  void PublishRecording();

  Scenario scenario_;
  VehicleParams params_;
  SumoResult sumo_;
  std::shared_ptr<const Terrain> terrain_;
  std::shared_ptr<const Path> path_;
  std::unique_ptr<VehicleSimulation> vehicle_;
  std::vector<double> s3d_, s2d_;  // driven polyline arc lengths, 3D and horizontal
  TimeNs end_ns_ = 0;
  bool started_ = false;
  TruthSummary summary_;
  double sum_lateral_sq_ = 0.0;
  std::size_t samples_ = 0;
  double distance_at_60s_ = -1.0;

  struct Recording {
    StageCache::PendingEntry entry;  // dropped unless the truth runs to its end
    std::unique_ptr<BinaryWriter> writer;
  };
  std::unique_ptr<BinaryReader> replay_;
  std::optional<Recording> record_;
};

// The ego's SUMO vType: EgoVehicleTypeFor with 80 % of the acceleration limits.
EgoVehicleType EgoTypeFor(const VehicleParams& params);

// Writes traffic.csv (t_ns,id,x,y,z,yaw,pitch,length,width,height) and path.csv (the smoothed
// route: s,x,y,z,heading,curvature every 0.5 m) into dir.
void WriteTrafficCsv(const SumoResult& sumo, const std::filesystem::path& path);
void WritePathCsv(const Path& path, const Terrain& terrain, const std::filesystem::path& file);

}  // namespace statebench::sim
