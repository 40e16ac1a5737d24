// The sensor setup a scenario names in its `sensors:` field (docs/scenarios.md), with the
// scenario's `faults:` applied.
//
// `sensors:` is a setup file name, resolved the way vehicle files are (FindVehicleFile): next to
// the scenario, then `setups/` or `scenarios/setups/` in any parent folder of the scenario, then
// $STATEBENCH_SOURCE_DIR/scenarios/setups, then ./scenarios/setups of the working folder; a name
// without extension gets ".yaml". The scenario file itself is never the answer (the paper's
// scenarios and setups share their names). It may also be an inline setup map
// (docs/sensor-setup.md).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "sensors/sensor_setup.hpp"
#include "simulator/scenario.hpp"
#include "simulator/scenario_faults.hpp"
#include "simulator/scenario_mismatch.hpp"

namespace statebench::sim {

struct ScenarioSensors {
  sensors::SensorSetup setup;  // faults and mismatch applied: what the simulator uses
  std::string setup_yaml;      // the setup as written (file text, or the inline map): what the
                               // estimators are told
  ScenarioFaults faults;       // the faults that are not setup options (urban canyon)
  std::vector<SensorMismatch> mismatch;  // what the scenario's `mismatch:` drew (empty: none)
};

std::optional<std::filesystem::path> FindSensorSetupFile(const std::filesystem::path& scenario_file,
                                                         const std::string& name);

// Throws InputError naming the scenario file, line and field when `sensors:` is missing, names
// no known file, or the setup or the faults are bad.
ScenarioSensors LoadScenarioSensors(const Scenario& scenario);

}  // namespace statebench::sim
