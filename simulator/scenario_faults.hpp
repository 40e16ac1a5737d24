// The `faults:` field of a scenario (docs/scenarios.md): degradations injected into the sensors
// of its setup.
//
//   faults:
//     gnss_outages:              # appended to the receivers' own `outages` (no fix in [start,
//     end))
//       - {start_s: 60.0}                               # every GNSS receiver, to the end
//       - {sensors: [gnss_front], start_s: 20.0, end_s: 35.0}
//     urban_canyon: true         # or {elevation_mask_deg: 10, blocking_range_m: 1000}
//     sensor_outages:            # any sensor of the setup falls silent in [start, end)
//       - {sensors: [lidar_roof, gnss_front], start_s: 100.0, end_s: 160.0}
//     injected:                  # what broken sensors deliver (core/measurement_faults.hpp)
//       - {type: gnss_jump, start_s: 40, end_s: 45, offset_m: [100, 0, 0]}
//       - {type: non_finite, sensors: [imu], start_s: 30, end_s: 31, value: nan}
//
// `urban_canyon` lets the world's buildings, trees and terrain block the satellites of a synthetic
// constellation, which degrades the GNSS fixes (fixed -> float -> single -> none) by the visible
// count (sensors/urban_canyon_visibility.hpp). It is off unless asked for: the generated towns'
// streets are deep canyons that would take the RTK fix away most of the time.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/measurement_faults.hpp"
#include "core/time.hpp"
#include "core/yaml_node.hpp"
#include "sensors/sensor_setup.hpp"
#include "sensors/urban_canyon_visibility.hpp"

namespace statebench::sim {

// Measurements of the named sensors stamped in [start, end) are not delivered.
struct SensorOutage {
  std::vector<std::string> sensors;
  double start_s = 0.0;
  double end_s = 0.0;  // +inf: to the end

  bool Covers(const std::string& sensor_id, TimeNs stamp_ns) const;
};

struct ScenarioFaults {
  std::optional<sensors::SkyViewOptions> urban_canyon;  // set: satellites blocked by the world
  std::vector<SensorOutage> sensor_outages;
  std::vector<MeasurementFault> injected;  // in the scenario's order

  // Every fault acting on the measurement stream: the outages as gaps, then `injected`.
  std::vector<MeasurementFault> StreamFaults() const;
};

// Applies `faults` to `setup` and returns the faults that are not setup options. Throws
// InputError "file:line:col: field 'faults...': ..." on unknown keys, bad values, or sensor ids
// that are not GNSS receivers of the setup.
ScenarioFaults ApplyFaults(const YamlNode& faults, sensors::SensorSetup* setup);

}  // namespace statebench::sim
