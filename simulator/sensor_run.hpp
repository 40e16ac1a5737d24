// The whole simulation of a scenario as ONE measurement stream: truth (SUMO + vehicle model at
// 1 kHz, truth_simulation.hpp) -> every sensor of the scenario's setup (sensors/sensor_suite.hpp)
// -> measurements in arrival order.
//
// Wiring:
//   - setup: the scenario's `sensors:` with its `faults:` applied (scenario_sensors.hpp);
//   - lidar world: built from the SUMO run's lanes, junctions and traffic over the fitted terrain
//     (world_from_sumo.hpp); each lidar entry becomes a LidarSensorModel added to the suite;
//   - faults: the scenario's sensor outages and injected faults act on the stream between the
//     sensors and its reader (core/measurement_faults.hpp);
//   - urban canyon (when the scenario's faults ask for it, scenario_faults.hpp): the GNSS
//     receivers count the satellites of a synthetic constellation (seeded, above the scenario
//     origin) that the world's static surfaces do not block;
//   - seeds: the world layout and the constellation derive from the scenario seed (the place),
//     every sensor's error streams from the sensor seed (scenario seed unless overridden), so
//     Monte Carlo runs over sensor errors can keep the world and the traffic.
// Same scenario, options and seed: the same stream, bit for bit, on any number of threads.
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>

#include "core/measurement_faults.hpp"
#include "core/se3.hpp"
#include "sensors/cached_sensor_model.hpp"
#include "sensors/lidar_world.hpp"
#include "sensors/measurement_stream.hpp"
#include "sensors/urban_canyon_visibility.hpp"
#include "sensors/world_layout.hpp"
#include "simulator/cached_stages.hpp"
#include "simulator/scenario.hpp"
#include "simulator/scenario_sensors.hpp"
#include "simulator/sumo_run.hpp"
#include "simulator/truth_simulation.hpp"

namespace statebench::sim {

struct SensorRunOptions {
  std::optional<std::uint64_t> sensor_seed;  // default: the scenario seed
  sensors::WorldLayoutOptions layout;        // its seed is replaced by the scenario seed
  sensors::LidarWorldOptions world;
  // Satellites blocked by the world degrade the GNSS fixes; unset: as the scenario's faults say.
  std::optional<bool> urban_canyon;
  SumoRunOptions sumo;
  // The SUMO result and every sensor's stream come from (and go to) this cache when set
  // (cached_stages.hpp); the stream is the same, bit for bit. Only the defaults of `layout` and
  // `world` are part of the keys: leave them alone when caching.
  StageCacheUse cache;
};

class SensorRun : public sensors::MeasurementSource {
 public:
  // Loads the setup (before running anything, so a bad setup fails fast), runs SUMO with its
  // files in work_dir/sumo, builds the world. Throws InputError on bad scenario/setup/faults.
  SensorRun(const Scenario& scenario, const std::filesystem::path& work_dir,
            const SensorRunOptions& options = {});
  SensorRun(const SensorRun&) = delete;
  SensorRun& operator=(const SensorRun&) = delete;

  // The next measurement in arrival order; nothing once the truth has ended and every buffered
  // measurement is out.
  std::optional<Measurement> Next() override;

  // Called with every truth sample as it is generated (e.g. to write truth files or progress).
  void SetTruthObserver(std::function<void(const TruthSample&)> observer) {
    observer_ = std::move(observer);
  }

  const TruthSimulation& truth() const { return *truth_; }
  const ScenarioSensors& sensors() const { return sensors_; }
  // The lidar world (nullptr when the setup has no lidar and the urban canyon is off).
  std::shared_ptr<const sensors::LidarWorld> world() const { return world_; }
  std::uint64_t sensor_seed() const { return sensor_seed_; }
  // The scenario's outages and injected faults, with how many measurements each acted on.
  const MeasurementFaultInjector& faults() const { return faults_; }
  // Mount of the setup's first IMU (the vehicle's default IMU mount without one).
  SE3 T_body_imu() const;

 private:
  std::optional<TruthSample> NextTruth();
  // The end of the truth: the recorded streams are complete and go into the cache.
  void PublishRecordings();

  struct Recording {
    sensors::RecordingSensorModel* model = nullptr;  // owned by the suite
    StageCache::PendingEntry entry;                  // dropped unless the truth runs to its end
  };

  ScenarioSensors sensors_;
  std::uint64_t sensor_seed_ = 0;
  std::unique_ptr<TruthSimulation> truth_;
  std::shared_ptr<sensors::LidarWorld> world_;
  std::unique_ptr<sensors::MeasurementSource> source_;
  std::function<void(const TruthSample&)> observer_;
  StageCacheUse cache_;
  std::vector<Recording> recordings_;
  MeasurementFaultInjector faults_;
  std::deque<Measurement> pending_;       // delivered before the next measurement of the sensors
  std::optional<Measurement> lookahead_;  // read past the current arrival instant
};

}  // namespace statebench::sim
