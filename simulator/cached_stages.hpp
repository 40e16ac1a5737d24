// The simulation's expensive stages through the stage cache (core/stage_cache.hpp,
// docs/sweeps.md "The stage cache"): the SUMO run of a scenario, and each sensor's measurement
// stream (the lidar raycasts above all).
//
// Keys are SHA-256 hashes of exactly what a stage depends on, and of the build that computes it
// (`code_id`, e.g. the hash of the statebench executable), so a cached stage gives the same bits
// as a fresh one:
//   truth  (SUMO result): the scenario's network (and its XML files' content), ego, traffic,
//          sumo, duration, seed and origin, the vehicle file's content, the SUMO run options;
//   sensor stream: the truth key, the sensor's entry in the setup, the sensor seed and, for
//          GNSS receivers, the scenario's faults (outages, urban canyon).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "core/stage_cache.hpp"
#include "simulator/ego_vehicle_type.hpp"
#include "simulator/scenario.hpp"
#include "simulator/scenario_sensors.hpp"
#include "simulator/sumo_result.hpp"
#include "simulator/sumo_run.hpp"

namespace statebench::sim {

struct StageCacheUse {
  StageCache* cache = nullptr;  // nullptr: every stage is computed
  std::string code_id;          // identity of the build
  bool enabled() const { return cache != nullptr; }
};

// nullopt when the scenario file cannot be read (a scenario built in memory is never cached).
std::optional<std::string> TruthStageKey(const Scenario& scenario, const SumoRunOptions& options,
                                         const std::string& code_id);

// Key of each sensor of the setup, by id.
std::map<std::string, std::string> SensorStreamKeys(const Scenario& scenario,
                                                    const ScenarioSensors& sensors,
                                                    const std::string& truth_key,
                                                    std::uint64_t sensor_seed,
                                                    const std::string& code_id);

// Key of everything the estimators of a run are fed: the truth key, every sensor's stream key,
// the scenario's faults (outages and injected faults act on the streams) and its mismatch
// (mounts, clocks and the units drawn). nullopt when the truth is not cacheable.
std::optional<std::string> EstimatorInputsKey(const Scenario& scenario,
                                              const ScenarioSensors& sensors,
                                              const SumoRunOptions& options,
                                              std::uint64_t sensor_seed,
                                              const std::string& code_id);

// SimulateSumo, or its cached result (the network file is copied into work_dir/sumo either way,
// so a run folder looks the same). One process computes a key at a time; the others wait.
SumoResult SimulateSumoCached(const Scenario& scenario, const EgoVehicleType& ego_type,
                              const std::filesystem::path& work_dir,
                              const SumoRunOptions& options, const StageCacheUse& cache);

}  // namespace statebench::sim
