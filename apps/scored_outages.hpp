// The windows a run scores as GNSS outages (metrics.json "outages" and "during_outages"): the
// time the estimators ran without any GNSS fix by the scenario's design.
#pragma once

#include <vector>

#include "core/time.hpp"
#include "reports/trajectory_metrics.hpp"
#include "simulator/scenario_sensors.hpp"

namespace statebench::app {

// Clipped to [0, end_ns), sorted by start:
//   - GNSS outages every receiver of the setup has (the scenario's `faults: gnss_outages` give
//     them to all receivers unless they name some);
//   - `faults: sensor_outages` windows that silence every GNSS receiver of the setup (other
//     sensors may go silent with them, as the lidar does in setup2_imu_only_60s).
// A setup without GNSS has no outage windows.
std::vector<reports::OutageWindow> ScoredOutages(const sim::ScenarioSensors& sensors,
                                                 TimeNs end_ns);

}  // namespace statebench::app
