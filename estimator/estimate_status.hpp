// The status an estimator puts on its estimates (core/state.hpp EstimateStatus), from what its
// diagnostics already record: when the absolute-position sensors (GNSS antennas) were last
// accepted and when it last re-initialised after being lost.
#pragma once

#include <string>
#include <vector>

#include "core/state.hpp"
#include "estimator/estimator_diagnostics.hpp"

namespace statebench::est {

// No absolute position accepted for this long: dead reckoning (a 10 Hz receiver misses 50 fixes;
// a gated-out fix or two does not change the status).
inline constexpr double kDeadReckoningAfterS = 5.0;
// For this long after a re-initialisation the estimate is "recovering": the fault tests
// (tests/estimator/fault_recovery_test.cpp) show the error back to normal within it.
inline constexpr double kRecoveringForS = 10.0;

// position_sensors: the ids of the setup's absolute-position sensors (empty: a local frame).
EstimateStatus StatusAt(const EstimatorDiagnostics& diagnostics,
                        const std::vector<std::string>& position_sensors, TimeNs t_ns);

}  // namespace statebench::est
